// The live table under a writer that swaps tables as fast as it can while a
// reader queries: every read sees one whole table, never a mix; and its
// allocation count. Its single-task checks are portable tests, run on the host
// and on the Cortex-M7 (tests/portable/platform_live_table_test.cpp).
#include <catch2/catch.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <thread>

#include "alloc_counter.hpp"
#include "trueaxis/macros/live_table.hpp"

namespace {

// A table whose every entry carries its generation: a mix shows as two values.
struct Table {
  std::array<std::uint64_t, 512> entries{};
};

Table table_of(std::uint64_t generation) {
  Table t;
  t.entries.fill(generation);
  return t;
}

}  // namespace

TEST_CASE("a reader never sees a mix while a writer swaps tables", "[live]") {
  trueaxis::macros::LiveTable<Table> live;
  live.publish(table_of(1));
  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> published{1};
  // A commit every ~20 us: far more often than a controller ever commits a
  // table, and still many swaps during the reads below.
  std::thread writer([&] {
    for (std::uint64_t g = 2; !stop.load(); ++g) {
      live.publish(table_of(g));
      published.store(g);
      const auto until = std::chrono::steady_clock::now() + std::chrono::microseconds(20);
      while (std::chrono::steady_clock::now() < until) {
      }
    }
  });
  std::uint64_t reads = 0, mixes = 0, refused = 0, last = 0, backwards = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(300);
  while (std::chrono::steady_clock::now() < deadline && reads < 2'000'000) {
    std::uint64_t lo = 0, hi = 0;
    const bool ok = live.read([&](const Table& t) {
      lo = hi = t.entries[0];
      for (std::uint64_t e : t.entries) {
        lo = e < lo ? e : lo;
        hi = e > hi ? e : hi;
      }
    });
    ++reads;
    if (!ok) {
      ++refused;
      continue;
    }
    if (lo != hi) ++mixes;
    if (lo < last) ++backwards;
    last = lo;
  }
  stop.store(true);
  writer.join();
  INFO("reads " << reads << ", refused " << refused << ", tables published " << published.load());
  CHECK(mixes == 0);
  CHECK(backwards == 0);
  CHECK(published.load() > 100);  // the writer really swapped while we read
  CHECK(refused < reads / 100);
}

TEST_CASE("read and publish allocate nothing", "[live][alloc]") {
  static trueaxis::macros::LiveTable<Table> live;
  const Table t = table_of(3);
  std::uint64_t seen = 0;
  bool ok = false;
  std::size_t allocations = 0;
  {
    const trueaxis::test::AllocationScope scope;
    live.publish(t);
    ok = live.read([&](const Table& x) { seen = x.entries[5]; });
    allocations = scope.count();
  }
  CHECK(ok);
  CHECK(seen == 3);
  CHECK(allocations == 0);
}
