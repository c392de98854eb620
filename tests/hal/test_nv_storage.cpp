#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

#include "trueaxis/hal/posix/file_nv_storage.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"

using trueaxis::hal::IoStatus;

namespace {

// A fresh path in the temporary directory, removed at the end of the scope.
struct TempPath {
  std::string path;
  TempPath() {
    char name[] = "/tmp/trueaxis-nv-XXXXXX";
    const int fd = mkstemp(name);
    REQUIRE(fd >= 0);
    ::close(fd);
    std::remove(name);
    path = name;
  }
  ~TempPath() { std::remove(path.c_str()); }
};

// The range checks every NvStorage shares (nv_storage.hpp contract 1).
void check_ranges(trueaxis::hal::NvStorage& nv, std::size_t size) {
  std::array<std::uint8_t, 8> buf{1, 2, 3, 4, 5, 6, 7, 8};
  CHECK(nv.size_bytes() == size);
  CHECK(nv.write(size - 8, buf.data(), 8) == IoStatus::kOk);
  CHECK(nv.write(size - 7, buf.data(), 8) == IoStatus::kOutOfRange);
  CHECK(nv.write(size + 1, buf.data(), 0) == IoStatus::kOutOfRange);
  CHECK(nv.read(static_cast<std::size_t>(-1), buf.data(), 2) == IoStatus::kOutOfRange);
  std::array<std::uint8_t, 8> back{};
  CHECK(nv.read(size - 8, back.data(), 8) == IoStatus::kOk);
  CHECK(back == buf);
}

}  // namespace

TEST_CASE("RAM storage checks ranges and keeps what is written", "[hal]") {
  std::array<std::uint8_t, 64> bytes{};
  trueaxis::hal::RamNvStorage nv(bytes.data(), bytes.size());
  check_ranges(nv, bytes.size());
}

TEST_CASE("file storage checks ranges, reads a new file as zeros and keeps writes over a reopen", "[hal]") {
  TempPath tmp;
  {
    trueaxis::hal::FileNvStorage nv;
    REQUIRE(nv.open(tmp.path.c_str(), 256) == IoStatus::kOk);
    std::array<std::uint8_t, 16> zeros{};
    REQUIRE(nv.read(100, zeros.data(), zeros.size()) == IoStatus::kOk);
    for (std::uint8_t b : zeros) CHECK(b == 0);
    check_ranges(nv, 256);
  }
  trueaxis::hal::FileNvStorage again;
  REQUIRE(again.open(tmp.path.c_str(), 256) == IoStatus::kOk);
  std::array<std::uint8_t, 8> back{};
  REQUIRE(again.read(248, back.data(), 8) == IoStatus::kOk);
  CHECK(back[0] == 1);
  CHECK(back[7] == 8);
}

TEST_CASE("file storage refuses everything before it is opened or when the path is unusable", "[hal]") {
  trueaxis::hal::FileNvStorage nv;
  std::uint8_t b = 0;
  CHECK(nv.read(0, &b, 1) == IoStatus::kOutOfRange);
  CHECK(nv.write(0, &b, 1) == IoStatus::kOutOfRange);
  CHECK(nv.open("/nonexistent-dir/trueaxis.nv", 64) == IoStatus::kIoError);
  CHECK(nv.size_bytes() == 0);
}
