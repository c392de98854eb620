// List<T>: a constexpr view of a static array (pointer and count), so that a
// method descriptor can name "no rows" or "no status codes" as well as a table.
// No allocation; the array must outlive the view (every use is a static table).
#pragma once

#include <cstddef>

namespace trueaxis::macros {

template <typename T>
struct List {
  const T* data = nullptr;
  std::size_t size = 0;

  constexpr const T* begin() const { return data; }
  constexpr const T* end() const { return data + size; }
  constexpr const T& operator[](std::size_t i) const { return data[i]; }
  constexpr bool empty() const { return size == 0; }
};

template <typename T, std::size_t N>
constexpr List<T> list_of(const T (&table)[N]) {
  return {table, N};
}

}  // namespace trueaxis::macros
