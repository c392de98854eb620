// Fakes for the hal interfaces: trivial subclasses, as the interfaces intend.
// Heap-free, so the portable tests use them on the Cortex-M7 as well.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "trueaxis/hal/clock.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "trueaxis/macros/records.hpp"

namespace trueaxis::test {

class FakeClock final : public hal::Clock {
 public:
  std::uint64_t now = 1000;
  std::uint64_t step = 7;
  std::uint32_t wall = 0;  // the wall clock (hal/clock.hpp): 0, none

 private:
  std::uint64_t do_now_us() override { return now += step; }
  std::uint32_t do_wall_s() override { return wall; }
};

// RAM storage that can refuse writes, or stop after a number of bytes as a power
// cut would (the write returns kIoError and the bytes after the cut keep their
// old value). It notes the lowest and highest byte each write touched since
// forget_writes(), so a test can tell which record a write landed in.
class FlakyStorage final : public hal::NvStorage {
 public:
  std::array<std::uint8_t, macros::kRequiredStorageBytes> bytes{};
  bool refuse = false;
  bool refuse_reads = false;
  std::size_t unreadable_first = 0;  // reads touching [unreadable_first, unreadable_end) fail
  std::size_t unreadable_end = 0;
  bool land_then_fail = false;  // the bytes land, then the write reports failure (fsync failed)
  long cut_after_bytes = -1;    // -1: no cut
  std::size_t written_first = SIZE_MAX;  // lowest offset written since forget_writes()
  std::size_t written_end = 0;           // one past the highest
  std::size_t written_bytes = 0;

  // Blank, powered and obliging again, as a new device.
  void reset() {
    bytes.fill(0);
    refuse = refuse_reads = land_then_fail = false;
    unreadable_first = unreadable_end = 0;
    cut_after_bytes = -1;
    forget_writes();
  }

  void forget_writes() {
    written_first = SIZE_MAX;
    written_end = 0;
    written_bytes = 0;
  }

 private:
  std::size_t do_size_bytes() const override { return bytes.size(); }
  hal::IoStatus do_read(std::size_t offset, std::uint8_t* out, std::size_t length) override {
    if (refuse_reads) return hal::IoStatus::kIoError;
    if (offset < unreadable_end && offset + length > unreadable_first) return hal::IoStatus::kIoError;
    for (std::size_t i = 0; i < length; ++i) out[i] = bytes[offset + i];
    return hal::IoStatus::kOk;
  }
  hal::IoStatus do_write(std::size_t offset, const std::uint8_t* data, std::size_t length) override {
    if (refuse) return hal::IoStatus::kIoError;
    if (offset < written_first) written_first = offset;
    if (offset + length > written_end) written_end = offset + length;
    written_bytes += length;
    for (std::size_t i = 0; i < length; ++i) {
      if (cut_after_bytes >= 0 && static_cast<long>(i) >= cut_after_bytes) return hal::IoStatus::kIoError;
      bytes[offset + i] = data[i];
    }
    return land_then_fail ? hal::IoStatus::kIoError : hal::IoStatus::kOk;
  }
};

}  // namespace trueaxis::test
