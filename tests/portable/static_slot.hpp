// Room for one object in static storage, constructed and destroyed on demand:
// a Module holds its sessions and tables (tens of kilobytes), more than the
// Cortex-M7 test image's stack should carry, and it cannot be reassigned.
// Placement new only: nothing comes from a heap.
#pragma once

#include <new>
#include <utility>

namespace trueaxis::test {

template <typename T>
class StaticSlot {
 public:
  StaticSlot() = default;
  StaticSlot(const StaticSlot&) = delete;
  StaticSlot& operator=(const StaticSlot&) = delete;
  // No destructor: a static object with one would need atexit registration,
  // which the bare-metal image does not have. reset() ends the object's life.

  template <typename... Args>
  T& emplace(Args&&... args) {
    reset();
    object_ = new (static_cast<void*>(bytes_)) T(std::forward<Args>(args)...);
    return *object_;
  }

  void reset() {
    if (object_ != nullptr) object_->~T();
    object_ = nullptr;
  }

 private:
  alignas(T) unsigned char bytes_[sizeof(T)];
  T* object_ = nullptr;
};

}  // namespace trueaxis::test
