// The live table (macros/include/trueaxis/macros/live_table.hpp), on the host
// and on the Cortex-M7, in one task: no table before a publish, and a publish
// leaves the previous buffer untouched. tests/macros/test_live_table.cpp keeps
// the host's checks under a concurrent writer and the allocation count.
#include <cstddef>
#include <cstdint>

#include "portable_test.hpp"
#include "trueaxis/macros/live_table.hpp"

namespace {

// A table whose every entry carries its generation: a mix shows as two values.
struct Table {
  std::uint64_t entries[512] = {};
};

Table table_of(std::uint64_t generation) {
  Table t;
  for (std::uint64_t& e : t.entries) e = generation;
  return t;
}

// Static (two 4 KiB buffers each): the target's stack is 64 KiB. Each case
// uses its own, as new.
trueaxis::macros::LiveTable<Table> g_first_live;
trueaxis::macros::LiveTable<Table> g_second_live;

}  // namespace

TA_TEST("live table: a read before any publish finds no table") {
  trueaxis::macros::LiveTable<Table>& live = g_first_live;
  TA_CHECK(!live.has_table());
  bool called = false;
  TA_CHECK(!live.read([&](const Table&) { called = true; }));
  TA_CHECK(!called);
  live.publish(table_of(7));
  std::uint64_t seen = 0;
  TA_CHECK(live.read([&](const Table& t) { seen = t.entries[100]; }));
  TA_CHECK_EQ(seen, 7u);
  live.clear();
  TA_CHECK(!live.read([&](const Table&) {}));
}

TA_TEST("live table: publish keeps the previous live buffer untouched") {
  trueaxis::macros::LiveTable<Table>& live = g_second_live;
  live.publish(table_of(1));
  const Table* first = nullptr;
  TA_CHECK(live.read([&](const Table& t) { first = &t; }));
  TA_REQUIRE(first != nullptr);
  live.publish(table_of(2));
  TA_CHECK_EQ(first->entries[0], 1u);  // the old buffer is still table 1
  std::uint64_t seen = 0;
  TA_CHECK(live.read([&](const Table& t) { seen = t.entries[0]; }));
  TA_CHECK_EQ(seen, 2u);
}
