// Host throughput of macros::checksum::crc32 (the keyed store's CRC-32): bytes per second
// over a 64 KiB buffer, best of several runs, so a work-offset save's share of a
// Modbus write can be judged.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "trueaxis/macros/keyed_store.hpp"
#include "trueaxis/sim/program.hpp"

constexpr const char* kHelp =
    "usage: bench_crc_host\n"
    "  Host throughput of the keyed store's CRC-32 over a 64 KiB buffer, best of several runs.\n"
    "  --help, --version  this text; the version line\n";

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "bench_crc_host", kHelp)) return 0;
  std::vector<std::uint8_t> data(64 * 1024);
  std::uint32_t x = 12345;
  for (auto& b : data) b = static_cast<std::uint8_t>(x = x * 1103515245u + 12345u);
  constexpr int kRepeats = 400;  // 25.6 MiB per run
  double best_s = 1e9;
  std::uint32_t sink = 0;
  for (int run = 0; run < 7; ++run) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < kRepeats; ++r) sink = sink * 31u + trueaxis::macros::checksum::crc32(data.data(), data.size());
    const auto t1 = std::chrono::steady_clock::now();
    best_s = std::min(best_s, std::chrono::duration<double>(t1 - t0).count());
  }
  const double bytes = static_cast<double>(data.size()) * kRepeats;
  // A work-offset record: 20-byte header + 360-byte payload.
  std::printf("crc32: %.0f MB/s (%.2f ns/byte); a 380-byte work-offset record: %.2f us (check %08x)\n",
              bytes / best_s / 1e6, best_s / bytes * 1e9, best_s / bytes * 380.0 * 1e6,
              static_cast<unsigned>(sink));
  return 0;
}
