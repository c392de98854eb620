// One block of memory that several methods take turns to use. The module owns
// two: one for the calibration sessions, one for the running macro's work
// (builders, the last computation, the decode scratch of start()).
//
// Contract
//  1. The module sizes each block at compile time for the largest and most
//     strictly aligned type any built method puts in it (module.hpp), so a
//     method reaches an arena only through its context's typed accessors
//     (method_context.hpp), with the types its descriptor declares.
//  2. open<T>() ends whatever the arena held (its owner simply loses it: the
//     types are trivially destructible, checked at compile time) and makes it
//     a value-initialised T. find<T>() returns that T while no other type has
//     been opened since, else nullptr. A type is its own tag (no RTTI).
//  3. No allocation, no exceptions; open<T>() costs one pass over sizeof(T)
//     bytes (the value-initialisation), find<T>() one comparison.
#pragma once

#include <cstddef>
#include <new>
#include <type_traits>

namespace trueaxis::macros {

namespace detail {
template <typename T>
struct ArenaTag {
  static constexpr char id = 0;
};
}  // namespace detail

// The bytes of an arena, owned by the module: Bytes and Align from the built
// methods' types (at least 1 byte, so that an empty method set still compiles).
template <std::size_t Bytes, std::size_t Align>
struct ArenaStorage {
  static constexpr std::size_t kBytes = Bytes;
  static constexpr std::size_t kAlign = Align;
  alignas(Align) unsigned char bytes[Bytes > 0 ? Bytes : 1] = {};
  const char* owner = nullptr;
};

// The T an arena's storage holds, or nullptr (contract 2), read-only.
template <typename T, std::size_t Bytes, std::size_t Align>
const T* arena_find(const ArenaStorage<Bytes, Align>& storage) {
  const void* bytes = storage.bytes;  // aligned for every type the arena holds (contract 1)
  return storage.owner == &detail::ArenaTag<T>::id ? std::launder(static_cast<const T*>(bytes)) : nullptr;
}

// What a macro sees of an arena.
class Arena {
 public:
  template <std::size_t Bytes, std::size_t Align>
  explicit Arena(ArenaStorage<Bytes, Align>& storage) : bytes_(storage.bytes), owner_(storage.owner) {}

  template <typename T>
  T& open() {
    static_assert(std::is_trivially_destructible<T>::value, "an arena's owner loses its object without a destructor");
    owner_ = nullptr;
    T* t = new (bytes_) T();
    owner_ = &detail::ArenaTag<T>::id;
    return *t;
  }

  template <typename T>
  T* find() const {
    return owner_ == &detail::ArenaTag<T>::id ? std::launder(static_cast<T*>(bytes_)) : nullptr;
  }

  // True while nothing has been opened since start.
  bool empty() const { return owner_ == nullptr; }

 private:
  void* bytes_;  // aligned for every type the arena holds (contract 1)
  const char*& owner_;
};

}  // namespace trueaxis::macros
