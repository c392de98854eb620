// Host time of macro 9810: one command write plus the step that runs it, on a
// Module over RAM storage. Prints the median and p99 of per-run times over
// batches (each batch's mean, so the clock's resolution does not dominate).
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <vector>

#include "trueaxis/hal/clock.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/sim/program.hpp"

namespace {

class ChronoClock final : public trueaxis::hal::Clock {
  std::uint64_t do_now_us() override {
    return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                          std::chrono::steady_clock::now().time_since_epoch())
                                          .count());
  }
};

}  // namespace

constexpr const char* kHelp =
    "usage: bench_level_host\n"
    "  Host time of macro 9810 (a command write plus the step that runs it) on a Module over\n"
    "  RAM storage: the median and p99 of per-run times over batches.\n"
    "  --help, --version  this text; the version line\n";

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "bench_level_host", kHelp)) return 0;
  namespace m = trueaxis::macros;
  static std::array<std::uint8_t, m::kRequiredStorageBytes> nv{};
  trueaxis::hal::RamNvStorage storage(nv.data(), nv.size());
  ChronoClock clock;
  m::Module module(storage, clock);
  if (module.start() != trueaxis::core::Status::kOk) return 1;
  const double points[3][3] = {{0, 0, 10}, {100, 0, 30}, {0, 100, 12}};
  for (int k = 0; k < 3; ++k) {
    const std::uint16_t base = k == 0 ? m::var::kG57 : (k == 1 ? m::var::kG58 : m::var::kG59);
    if (module.write(base, 3, points[k]) != m::AccessFault::kNone) return 1;
  }
  constexpr int kBatches = 200;
  constexpr int kPerBatch = 500;
  std::vector<double> ns;
  ns.reserve(kBatches);
  const double cmd = 9810.0;
  for (int b = 0; b < kBatches; ++b) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < kPerBatch; ++i) {
      if (module.write(m::var::kCmd, 1, &cmd) != m::AccessFault::kNone) return 1;
      module.step();
    }
    const auto t1 = std::chrono::steady_clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / kPerBatch);
  }
  if (module.value(m::var::kStatus) != 2.0) return 1;
  std::sort(ns.begin(), ns.end());
  std::printf("macro 9810 on the host: median %.0f ns, p99 %.0f ns per run (%d batches of %d)\n",
              ns[ns.size() / 2], ns[ns.size() * 99 / 100], kBatches, kPerBatch);
  return 0;
}
