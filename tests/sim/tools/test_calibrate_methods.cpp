// trueaxis-calibrate's one table of methods against the module's one method
// list: every built method that stores a table has an entry, every entry is
// such a method, and --store names the record the method's descriptor gives.
#include <catch2/catch.hpp>

#include <string>

#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"

namespace m = trueaxis::macros;
namespace sim = trueaxis::sim;

TEST_CASE("the calibrate command's methods are the built methods that store a table", "[calibrate]") {
  using Built = m::BuiltMethods;
  std::size_t storing = 0;
  for (std::size_t i = 0; i < Built::kCount; ++i) {
    if (!Built::kHasTable[i]) continue;
    ++storing;
    INFO(Built::kNames[i]);
    CHECK(sim::find_calibrate_method(Built::kNames[i]) != nullptr);
  }
  std::size_t entries = 0;
  for (const sim::CalibrateMethod& c : sim::calibrate_methods()) {
    ++entries;
    INFO(c.name);
    const m::RecordSpec* record = sim::stored_record(c.name);
    REQUIRE(record != nullptr);
    CHECK(record->key != 0);
  }
  CHECK(entries == storing);
  CHECK(sim::stored_record("level") == nullptr);  // levels, stores no table
  CHECK(sim::stored_record("nonsense") == nullptr);
}
