// NvStorage over a caller-owned byte array: the fake for host tests and the
// storage of boards whose battery-backed RAM is plain memory (mps2-an500 here).
// Writes are durable when they return, as RAM that keeps its content is.
#pragma once

#include <cstring>

#include "trueaxis/hal/nv_storage.hpp"

namespace trueaxis::hal {

class RamNvStorage final : public NvStorage {
 public:
  RamNvStorage(std::uint8_t* bytes, std::size_t size) : bytes_(bytes), size_(size) {}

 private:
  std::size_t do_size_bytes() const override { return size_; }
  IoStatus do_read(std::size_t offset, std::uint8_t* out, std::size_t length) override {
    std::memcpy(out, bytes_ + offset, length);
    return IoStatus::kOk;
  }
  IoStatus do_write(std::size_t offset, const std::uint8_t* data, std::size_t length) override {
    std::memcpy(bytes_ + offset, data, length);
    return IoStatus::kOk;
  }

  std::uint8_t* bytes_;
  std::size_t size_;
};

}  // namespace trueaxis::hal
