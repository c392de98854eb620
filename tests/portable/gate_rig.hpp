// What the gate tests share (tests/portable/*_gates_test.cpp, gates.hpp): a
// configuration write, and a computation a gate must refuse, checked to change
// nothing: its results, and the stored table's answer to a query.
#pragma once

#include <cstdint>

#include "module_rig.hpp"
#include "portable_test.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/module.hpp"

namespace trueaxis::test {

inline void configure(ModuleRig& rig, std::uint16_t n, double value) {
  TA_REQUIRE(rig.unlock());
  TA_REQUIRE(rig.put(n, value) == macros::AccessFault::kNone);
  TA_REQUIRE(rig.lock());
}

// A query's answer: its #9001 and three of its results.
struct Answer {
  double status = 0.0;
  core::Vec3 v = core::Vec3::Zero();
  bool operator==(const Answer& o) const { return status == o.status && (status != kDone || (v - o.v).norm() == 0.0); }
};

// What a gate refused: the code and #9012 .. #9014.
struct Refused {
  core::Status code = core::Status::kOk;
  double item = 0.0, value = 0.0, limit = 0.0;
};

// Runs `build` (returning its #9001), which must fail; `query` (returning an
// Answer) must answer as before it, the results must be as they were, and
// storage too but for the measuring log, whose newest entry is the refusal.
template <typename Build, typename Query>
Refused refused(ModuleRig& rig, Build build, Query query) {
  const Answer before_answer = query(rig);
  rig.snapshot();
  const ModuleRig::Results before = rig.results();
  Refused r;
  if (build(rig) != kError) {
    TA_CHECK(!"the computation was expected to be refused");
    return r;
  }
  r = {rig.code(), rig.get(macros::var::kGateItem), rig.get(macros::var::kGateValue), rig.get(macros::var::kGateLimit)};
  TA_CHECK(ModuleRig::logs_refusal(r.code) || !macros::kHasLog);  // a gate's refusal is logged
  TA_CHECK(rig.unchanged_after(r.code));
  TA_CHECK(rig.results() == before);
  TA_CHECK(query(rig) == before_answer);
  return r;
}

}  // namespace trueaxis::test
