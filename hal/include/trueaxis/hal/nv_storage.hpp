// Non-volatile storage: a byte-addressed region that keeps its content over a
// restart (a file on the host, battery-backed RAM or flash on a controller).
//
// Contract
//  1. read/write check the range and forward to the platform; a range outside
//     [0, size_bytes()) returns kOutOfRange and touches nothing.
//  2. write returns kOk only once the bytes are durable (a power cut after kOk
//     cannot lose them). A power cut during write may leave any subset of the
//     written bytes changed; nothing outside the range changes. Callers that must
//     survive that keep two copies (macros/persistent_store.hpp does).
//  3. No allocation, no exceptions. Objects are owned by main and passed by
//     reference; the destructor is protected so no one deletes through this type.
#pragma once

#include <cstddef>
#include <cstdint>

namespace trueaxis::hal {

enum class IoStatus : std::uint8_t {
  kOk = 0,
  kOutOfRange = 1,  // the range does not fit in the device
  kIoError = 2,     // the device reported a failure
};

class NvStorage {
 public:
  NvStorage(const NvStorage&) = delete;
  NvStorage& operator=(const NvStorage&) = delete;

  std::size_t size_bytes() const { return do_size_bytes(); }

  [[nodiscard]] IoStatus read(std::size_t offset, std::uint8_t* out, std::size_t length) {
    if (!fits(offset, length)) return IoStatus::kOutOfRange;
    return do_read(offset, out, length);
  }

  [[nodiscard]] IoStatus write(std::size_t offset, const std::uint8_t* data, std::size_t length) {
    if (!fits(offset, length)) return IoStatus::kOutOfRange;
    return do_write(offset, data, length);
  }

 protected:
  NvStorage() = default;
  ~NvStorage() = default;

 private:
  bool fits(std::size_t offset, std::size_t length) const {
    const std::size_t size = do_size_bytes();
    return offset <= size && length <= size - offset;
  }

  virtual std::size_t do_size_bytes() const = 0;
  virtual IoStatus do_read(std::size_t offset, std::uint8_t* out, std::size_t length) = 0;
  virtual IoStatus do_write(std::size_t offset, const std::uint8_t* data, std::size_t length) = 0;
};

}  // namespace trueaxis::hal
