#include "trueaxis/hal/posix/file_nv_storage.hpp"

#include <cerrno>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace trueaxis::hal {

FileNvStorage::~FileNvStorage() { close(); }

IoStatus FileNvStorage::open(const char* path, std::size_t size_bytes) {
  close();
  // O_DSYNC: each pwrite returns once its bytes are durable, one system call
  // where pwrite + fsync took two (a work-offset write is on a PLC's hot path).
  const int fd = ::open(path, O_RDWR | O_CREAT | O_CLOEXEC | O_DSYNC, 0644);
  if (fd < 0) return IoStatus::kIoError;
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    ::close(fd);
    return IoStatus::kIoError;
  }
  if (static_cast<std::size_t>(st.st_size) < size_bytes) {
    // ftruncate extends with zero bytes; fsync so a new device is durable too.
    if (::ftruncate(fd, static_cast<off_t>(size_bytes)) != 0 || ::fsync(fd) != 0) {
      ::close(fd);
      return IoStatus::kIoError;
    }
  }
  fd_ = fd;
  size_ = size_bytes;
  return IoStatus::kOk;
}

void FileNvStorage::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  size_ = 0;
}

IoStatus FileNvStorage::do_read(std::size_t offset, std::uint8_t* out, std::size_t length) {
  std::size_t done = 0;
  while (done < length) {
    const ssize_t n = ::pread(fd_, out + done, length - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return IoStatus::kIoError;
    done += static_cast<std::size_t>(n);
  }
  return IoStatus::kOk;
}

IoStatus FileNvStorage::do_write(std::size_t offset, const std::uint8_t* data, std::size_t length) {
  std::size_t done = 0;
  while (done < length) {
    const ssize_t n = ::pwrite(fd_, data + done, length - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return IoStatus::kIoError;
    done += static_cast<std::size_t>(n);
  }
  return IoStatus::kOk;
}

}  // namespace trueaxis::hal
