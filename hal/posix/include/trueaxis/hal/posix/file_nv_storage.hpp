// NvStorage in a file of fixed size: the host's stand-in for a controller's
// battery-backed RAM or flash.
//
// Contract
//  1. open(path, size) opens or creates the file. A new file, or the part of a
//     shorter one beyond its end, reads as zero bytes (ftruncate); a longer file
//     is used as is and only its first `size` bytes are addressed.
//  2. The file is opened O_DSYNC: write returns kOk only after pwrite of every
//     byte succeeded, each returning once its bytes are on the disk (NvStorage
//     contract 2). Any failure is kIoError.
//  3. Before a successful open, size_bytes() is 0, so every access is
//     kOutOfRange. The destructor closes the file.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/hal/nv_storage.hpp"

namespace trueaxis::hal {

class FileNvStorage final : public NvStorage {
 public:
  FileNvStorage() = default;
  ~FileNvStorage();

  // kOk, or kIoError when the file cannot be opened, created or sized.
  [[nodiscard]] IoStatus open(const char* path, std::size_t size_bytes);
  void close();

 private:
  std::size_t do_size_bytes() const override { return size_; }
  IoStatus do_read(std::size_t offset, std::uint8_t* out, std::size_t length) override;
  IoStatus do_write(std::size_t offset, const std::uint8_t* data, std::size_t length) override;

  int fd_ = -1;
  std::size_t size_ = 0;
};

}  // namespace trueaxis::hal
