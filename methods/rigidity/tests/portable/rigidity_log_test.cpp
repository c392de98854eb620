// The measuring log (macros/measuring_log.hpp, module.hpp contract 9), driven
// by M3's macros: what a calibration, a store and a check log, the window
// #9018 -> #9020..#9059, the ring of 32, the time (#9015, else the clock's
// wall time), a storage failure that loses the entry but not the macro, and a
// power cut at every byte of an append.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fakes.hpp"
#include "module_rig.hpp"
#include "portable_test.hpp"
#include "rigidity_fixture.hpp"
#include "store_fakes.hpp"
#include "trueaxis/macros/measuring_log.hpp"
#include "trueaxis/macros/records.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
namespace rf = trueaxis::test::rigidity;
using trueaxis::core::Status;
using trueaxis::test::kDone;
using trueaxis::test::ModuleRig;
using trueaxis::test::RigOptions;

constexpr double kT0 = 1'800'000'000.0;  // 2027-01-15T08:00:00Z

// The window's values for serial s: #9020..#9059.
struct Shown {
  double v[40];
  double serial() const { return v[0]; }
  double time() const { return v[1]; }
  double macro() const { return v[2]; }
  double type() const { return v[3]; }
  double verdict() const { return v[4]; }
  double stored() const { return v[5]; }
  double table_sequence() const { return v[6]; }
  double figures() const { return v[7]; }
  // Figure k's value j (0 kind, 1 item, 2 value, 3 sigma, 4 tolerance).
  double figure(std::size_t k, std::size_t j) const { return v[10 + 5 * k + j]; }
  bool operator==(const Shown& o) const { return std::memcmp(v, o.v, sizeof v) == 0; }
};

Shown show(ModuleRig& rig, double serial) {
  rig.set(v::kLogSelect, serial);
  Shown s{};
  for (std::uint16_t k = 0; k < 40; ++k) s.v[k] = rig.get(static_cast<std::uint16_t>(v::kLogSerial + k));
  return s;
}

double build_at(ModuleRig& rig, bool store, double time) {
  rig.set(v::kLogTime, time);
  return rf::build(rig, store);
}

}  // namespace

TA_TEST("the log: a calibration logs an entry, its store and then its check replace it; #9015 is its time") {
  ModuleRig rig;
  TA_CHECK_EQ(rig.get(v::kLogCount), 0.0);
  TA_CHECK_EQ(rig.get(v::kLogNewest), 0.0);
  rf::stream(rig);
  TA_REQUIRE(build_at(rig, false, kT0) == kDone);
  TA_CHECK_EQ(rig.get(v::kLogCount), 1.0);
  TA_CHECK_EQ(rig.get(v::kLogNewest), 1.0);
  const Shown first = show(rig, 1.0);
  TA_CHECK_EQ(first.serial(), 1.0);
  TA_CHECK_EQ(first.time(), kT0);
  TA_CHECK_EQ(first.macro(), 9832.0);
  TA_CHECK_EQ(first.type(), 0.0);      // a calibration
  TA_CHECK_EQ(first.verdict(), -1.0);  // without a verdict
  TA_CHECK_EQ(first.stored(), 0.0);
  TA_CHECK_EQ(first.table_sequence(), 0.0);  // nothing stored yet
  TA_CHECK_EQ(first.figures(), 2.0);
  TA_CHECK_EQ(first.figure(0, 0), 1.0);  // rigidity_worst: 20" at A = -60 or +60 (pose 1 or 5)
  TA_CHECK(first.figure(0, 1) == 1.0 || first.figure(0, 1) == 5.0);
  TA_CHECK_NEAR(first.figure(0, 2), 20.0, 1e-3);
  TA_CHECK(first.figure(0, 3) >= 0.0);
  TA_CHECK_EQ(first.figure(0, 4), 0.0);  // no tolerance
  TA_CHECK_EQ(first.figure(1, 0), 2.0);  // a_positioning_error_worst
  TA_CHECK_EQ(first.figure(2, 0), 0.0);  // no third figure
  TA_CHECK_EQ(show(rig, 2.0).serial(), 0.0);  // no such entry: zeros

  rig.set(v::kLogSelect, 1.0);
  rig.set(v::kArgQ, 1.0);
  TA_REQUIRE(rig.done(9834));  // any macro clears #9018, and the window with it
  TA_CHECK_EQ(rig.get(v::kLogSelect), 0.0);
  TA_CHECK_EQ(rig.get(v::kLogSerial), 0.0);
  TA_CHECK_EQ(rig.get(v::kLogMacro), 0.0);

  TA_REQUIRE(build_at(rig, true, kT0 + 60.0) == kDone);  // the store replaces the calibration
  TA_CHECK_EQ(rig.get(v::kLogCount), 1.0);
  const Shown stored = show(rig, 1.0);
  TA_CHECK_EQ(stored.time(), kT0 + 60.0);
  TA_CHECK_EQ(stored.stored(), 1.0);
  TA_CHECK(stored.table_sequence() >= 1.0);
  TA_CHECK_EQ(stored.figure(0, 2), first.figure(0, 2));

  TA_REQUIRE(build_at(rig, false, kT0 + 86400.0) == kDone);  // a stored entry is not replaced
  TA_CHECK_EQ(rig.get(v::kLogNewest), 2.0);
  rig.set(v::kLogTime, kT0 + 86460.0);
  rig.set(v::kArgQ, 0.0);
  TA_REQUIRE(rig.done(9836));  // the check replaces its calibration
  TA_CHECK_EQ(rig.get(v::kLogCount), 2.0);
  const Shown check = show(rig, 2.0);
  TA_CHECK_EQ(check.type(), 1.0);
  TA_CHECK_EQ(check.macro(), 9836.0);
  TA_CHECK_EQ(check.verdict(), 0.0);  // the same table: pass
  TA_CHECK_EQ(check.time(), kT0 + 86460.0);
  TA_CHECK_EQ(check.stored(), 0.0);
  TA_CHECK_EQ(check.table_sequence(), stored.table_sequence());  // the table it judged against
  TA_CHECK_EQ(check.figures(), 2.0);
  TA_CHECK_EQ(check.figure(0, 0), 1.0);  // rotation_change
  TA_CHECK_EQ(check.figure(0, 2), 0.0);  // the same table: no deviation
  TA_CHECK_EQ(check.figure(0, 4), rig.get(v::kRigidityCheckRotation));
  TA_CHECK_EQ(check.figure(1, 0), 2.0);  // a_positioning_error_change
  TA_CHECK_EQ(check.figure(1, 4), rig.get(v::kRigidityCheckAError));

  rig.set(v::kArgQ, 1.0);
  TA_REQUIRE(rig.done(9836));  // a figure's query logs nothing
  TA_CHECK_EQ(rig.get(v::kLogNewest), 2.0);
  rig.clock.wall = 1'900'000'000;
  TA_REQUIRE(rig.done(9836));  // Q = 0 (cleared): a second check appends; no #9015: the clock's wall time
  TA_CHECK_EQ(rig.get(v::kLogNewest), 3.0);
  TA_CHECK_EQ(show(rig, 3.0).time(), 1'900'000'000.0);

  // A restart keeps the log; nothing logged before it is replaced.
  TA_REQUIRE(rig.start() == Status::kOk);
  TA_CHECK_EQ(rig.get(v::kLogCount), 3.0);
  TA_CHECK_EQ(rig.get(v::kLogNewest), 3.0);
  TA_CHECK(show(rig, 2.0) == check);
}

TA_TEST("the log keeps the newest 32 entries; serials go on") {
  ModuleRig rig;
  rf::stream(rig);
  Shown third{};
  for (int i = 1; i <= 40; ++i) {
    TA_REQUIRE(build_at(rig, false, kT0 + i) == kDone);
    if (i == 9) third = show(rig, 9.0);
  }
  TA_CHECK_EQ(rig.get(v::kLogCount), 32.0);
  TA_CHECK_EQ(rig.get(v::kLogNewest), 40.0);
  TA_CHECK_EQ(show(rig, 8.0).serial(), 0.0);  // dropped
  TA_CHECK(show(rig, 9.0) == third);          // the oldest held, as it was
  TA_CHECK_EQ(show(rig, 40.0).time(), kT0 + 40.0);
}

TA_TEST("a refused append loses the entry, not the macro (#9019), and replaces nothing after it") {
  ModuleRig rig;
  rf::stream(rig);
  TA_REQUIRE(build_at(rig, false, kT0) == kDone);
  rig.storage().refuse = true;
  TA_REQUIRE(build_at(rig, false, kT0 + 1.0) == kDone);
  TA_CHECK_EQ(rig.get(v::kLogLost), 1.0);
  TA_CHECK_EQ(rig.get(v::kLogCount), 1.0);
  TA_CHECK_NEAR(rig.get(v::kRigidityWorst), 20.0, 1e-3);  // the build's own results
  rig.storage().refuse = false;
  // The store comes after a calibration whose entry was lost: it must not
  // replace the older calibration's entry 1.
  TA_REQUIRE(build_at(rig, true, kT0 + 2.0) == kDone);
  TA_CHECK_EQ(rig.get(v::kLogNewest), 2.0);
  TA_CHECK_EQ(show(rig, 1.0).stored(), 0.0);
  TA_CHECK_EQ(show(rig, 2.0).stored(), 1.0);
}

// The fault models walked (store_fakes.hpp): all three on the host; the
// Cortex-M7 under QEMU walks the first, a clean stop, at every byte (the
// store's own cut tests walk all three there).
#ifndef TRUEAXIS_LOG_CUT_FAULTS
#define TRUEAXIS_LOG_CUT_FAULTS 1
#endif

namespace {
std::uint8_t g_cut_bytes[m::kRequiredStorageBytes];
Shown g_before[m::kLogEntries];
}  // namespace

// Every append cut at every byte of its writes, under each fault model walked: after
// the restart the log holds every entry it held, unchanged, and the new one
// whole or not at all. Case index: 1000 x fault + budget.
TA_TEST("a power cut at any byte of an append keeps the log as it was, or with the new entry whole") {
  for (std::uint8_t& b : g_cut_bytes) b = 0;
  trueaxis::test::PowerCutStorage storage(g_cut_bytes, sizeof g_cut_bytes);
  ModuleRig rig(RigOptions{}.on(storage));
  rf::stream(rig);
  TA_REQUIRE(build_at(rig, false, kT0) == kDone);  // one entry before the cuts
  std::uint64_t seed = 0x10C0'FFEE;
  for (std::size_t f = 0; f < TRUEAXIS_LOG_CUT_FAULTS; ++f) {
    bool cut = true;
    std::size_t budget = 0;
    for (; cut; ++budget) {
      TA_CASE_INDEX(1000 * f + budget);
      const std::size_t n = static_cast<std::size_t>(rig.get(v::kLogCount));
      const double newest = rig.get(v::kLogNewest);
      for (std::size_t i = 0; i < n; ++i) g_before[i] = show(rig, newest - static_cast<double>(n - 1 - i));
      rf::stream(rig);
      storage.arm_cut(budget, trueaxis::test::kFaults[f], seed++);
      const double time = kT0 + static_cast<double>(1000 * f + budget + 1);
      TA_REQUIRE(build_at(rig, false, time) == kDone);  // the macro stands whatever the log
      cut = !storage.powered();
      storage.restore_power();
      TA_REQUIRE(rig.start() == Status::kOk);
      const double count = rig.get(v::kLogCount);
      const bool added = rig.get(v::kLogNewest) == newest + 1.0;
      TA_CHECK(added || rig.get(v::kLogNewest) == newest);
      TA_CHECK_EQ(count, static_cast<double>(added ? (n < m::kLogEntries ? n + 1 : n) : n));
      const std::size_t kept = added && n == m::kLogEntries ? n - 1 : n;
      for (std::size_t i = n - kept; i < n; ++i) TA_CHECK(show(rig, g_before[i].serial()) == g_before[i]);
      if (added) {
        const Shown e = show(rig, newest + 1.0);
        TA_CHECK_EQ(e.time(), time);
        TA_CHECK_EQ(e.figures(), 2.0);
        TA_CHECK_NEAR(e.figure(0, 2), 20.0, 1e-3);
      }
      TA_REQUIRE(budget < 4 * m::kLogBytes);
    }
    TA_CHECK(budget > m::kLogEntryBytes);  // the cuts walked the whole write
  }
}

namespace {
// 9832 R = 1 while locked: refused as table_locked (a refusal entry).
double refused_store(ModuleRig& rig, double time) {
  rig.lock();
  rig.set(v::kLogTime, time);
  rig.set(v::kArgR, 1.0);
  return rig.run(9832);
}
double check_at(ModuleRig& rig, double time) {
  rig.set(v::kLogTime, time);
  return rig.run(9836);
}
}  // namespace

TA_TEST("a refused store is logged as a refusal, in place of its own calibration, with the gate's figures") {
  ModuleRig rig;
  rf::stream(rig);
  TA_REQUIRE(build_at(rig, false, kT0) == kDone);  // measured ...
  TA_REQUIRE(refused_store(rig, kT0 + 1.0) == trueaxis::test::kError);  // ... then refused
  TA_CHECK_EQ(rig.code(), Status::kTableLocked);
  TA_CHECK_EQ(rig.get(v::kLogCount), 1.0);  // one entry: "measured, then refused"
  const Shown e = show(rig, 1.0);
  TA_CHECK_EQ(e.type(), static_cast<double>(m::LogType::kRefusal));
  TA_CHECK_EQ(e.time(), kT0 + 1.0);
  TA_CHECK_EQ(e.stored(), 0.0);
  TA_CHECK_EQ(e.figures(), 3.0);  // the refusal, then the build's two figures
  TA_CHECK_EQ(e.figure(0, 0), static_cast<double>(m::kRefusalFigure));
  TA_CHECK_EQ(e.figure(0, 3), static_cast<double>(static_cast<int>(Status::kTableLocked)));
  TA_CHECK_EQ(e.figure(1, 0), 1.0);  // rigidity_worst, as the calibration logged it
  TA_CHECK_NEAR(e.figure(1, 2), 20.0, 1e-3);
  TA_CHECK(rig.logged_refusal(Status::kTableLocked));
  // A failure that is no gate's and no store's (an empty session) logs nothing.
  TA_REQUIRE(rig.done(9830));
  TA_CHECK(rig.run(9832) == trueaxis::test::kError);
  TA_CHECK_EQ(rig.get(v::kLogNewest), 1.0);
}

TA_TEST("100 scratch calibrations and refused stores after a store and a check leave both in the log") {
  ModuleRig rig;
  rf::stream(rig);
  TA_REQUIRE(build_at(rig, true, kT0) == kDone);                 // 1: stored
  TA_REQUIRE(build_at(rig, false, kT0 + 10.0) == kDone);
  TA_REQUIRE(check_at(rig, kT0 + 20.0) == kDone);                // 2: its check
  const Shown stored = show(rig, 1.0);
  const Shown check = show(rig, 2.0);
  TA_REQUIRE(stored.stored() == 1.0 && check.type() == 1.0);
  for (int i = 0; i < 100; ++i) {
    TA_CASE_INDEX(i);
    TA_REQUIRE(build_at(rig, false, kT0 + 100.0 + 2 * i) == kDone);  // scratch: stores and checks nothing
    if (i % 10 == 9) {
      TA_REQUIRE(rig.unlock());
      TA_REQUIRE(refused_store(rig, kT0 + 101.0 + 2 * i) == trueaxis::test::kError);  // a failed store
    }
  }
  TA_CHECK_EQ(rig.get(v::kLogCount), 32.0);
  TA_CHECK(show(rig, 1.0) == stored);  // both held, as they were
  TA_CHECK(show(rig, 2.0) == check);
  TA_CHECK_EQ(rig.get(v::kLogNewest), 102.0);  // the scratch went on behind them
  TA_CHECK_EQ(show(rig, 73.0).serial(), 73.0);  // the newest 30 scratch entries
  TA_CHECK_EQ(show(rig, 72.0).serial(), 0.0);
  TA_CHECK_EQ(show(rig, 102.0).type(), static_cast<double>(m::LogType::kRefusal));  // measured, then refused
  // A check still judges, and logs, after them.
  TA_REQUIRE(build_at(rig, false, kT0 + 999.0) == kDone);
  TA_REQUIRE(check_at(rig, kT0 + 1000.0) == kDone);
  TA_CHECK_EQ(show(rig, 103.0).type(), 1.0);
  TA_CHECK(show(rig, 1.0) == stored);
}

TA_TEST("a full log drops the oldest entry of the lowest rank: scratch, then history, then the present table's checks") {
  ModuleRig rig;
  rf::stream(rig);
  TA_REQUIRE(build_at(rig, true, kT0) == kDone);  // 1: the first table, stored
  for (int i = 0; i < 5; ++i) {
    TA_REQUIRE(build_at(rig, false, kT0 + 10.0 * (i + 1)) == kDone);
    TA_REQUIRE(check_at(rig, kT0 + 10.0 * (i + 1) + 1.0) == kDone);  // 2..6: its checks
  }
  TA_REQUIRE(build_at(rig, false, kT0 + 100.0) == kDone);  // 7: scratch
  TA_REQUIRE(build_at(rig, false, kT0 + 110.0) == kDone);
  TA_REQUIRE(build_at(rig, true, kT0 + 200.0) == kDone);   // 8: the second table (in 8's place): 1..6 are history
  TA_CHECK_EQ(show(rig, 8.0).stored(), 1.0);
  TA_CHECK_EQ(show(rig, 7.0).stored(), 0.0);
  for (int i = 0; i < 24; ++i) {  // 9..32: checks of the second table fill the log
    TA_REQUIRE(build_at(rig, false, kT0 + 300.0 + 10.0 * i) == kDone);
    TA_REQUIRE(check_at(rig, kT0 + 301.0 + 10.0 * i) == kDone);
  }
  TA_CHECK_EQ(rig.get(v::kLogCount), 32.0);
  TA_CHECK_EQ(rig.get(v::kLogNewest), 32.0);
  // Scratch into the full log drops the scratch entry 7 (its own rank, the oldest); its check replaces it (33).
  TA_REQUIRE(build_at(rig, false, kT0 + 600.0) == kDone);
  TA_CHECK_EQ(show(rig, 7.0).serial(), 0.0);
  TA_CHECK_EQ(show(rig, 1.0).serial(), 1.0);
  TA_REQUIRE(check_at(rig, kT0 + 601.0) == kDone);
  TA_CHECK_EQ(show(rig, 33.0).type(), 1.0);
  // Now scratch ranks below every entry held: not kept, and nothing counted lost.
  TA_REQUIRE(build_at(rig, false, kT0 + 610.0) == kDone);
  TA_CHECK_EQ(rig.get(v::kLogNewest), 33.0);
  TA_CHECK_EQ(rig.get(v::kLogLost), 0.0);
  TA_REQUIRE(check_at(rig, kT0 + 611.0) == kDone);  // 34: a check drops the oldest history, 1
  TA_CHECK_EQ(show(rig, 34.0).type(), 1.0);
  TA_CHECK_EQ(show(rig, 1.0).serial(), 0.0);
  TA_CHECK_EQ(show(rig, 2.0).serial(), 2.0);
  for (int i = 0; i < 5; ++i) {  // 35..39: the rest of the history, 2..6
    TA_REQUIRE(build_at(rig, false, kT0 + 700.0 + 10.0 * i) == kDone);
    TA_REQUIRE(check_at(rig, kT0 + 701.0 + 10.0 * i) == kDone);
  }
  for (double s = 2.0; s <= 6.0; s += 1.0) TA_CHECK_EQ(show(rig, s).serial(), 0.0);
  TA_CHECK_EQ(show(rig, 9.0).serial(), 9.0);
  TA_REQUIRE(build_at(rig, false, kT0 + 800.0) == kDone);
  TA_REQUIRE(check_at(rig, kT0 + 801.0) == kDone);  // 40: then the present table's oldest check, 9
  TA_CHECK_EQ(show(rig, 9.0).serial(), 0.0);
  TA_CHECK_EQ(show(rig, 10.0).serial(), 10.0);
  TA_CHECK_EQ(show(rig, 8.0).stored(), 1.0);  // the present table's own entry is never dropped
  TA_CHECK_EQ(rig.get(v::kLogCount), 32.0);
}

TA_TEST("the log names a check's pose by the stored table's number, the table its entry carries; the check's own by its") {
  ModuleRig rig;
  rf::stored(rig);  // A -60, -30, 0, 30, 60: poses 1 .. 5
  // Measured again at A 0, 30, 60 only: the check's poses 1 .. 3, the stored table's 3 .. 5.
  TA_REQUIRE(rig.done(9830));
  for (int i = 2; i < rf::kPoses; ++i) {
    for (int k = 0; k < rf::kCPositions; ++k) {
      const double c = 360.0 / rf::kCPositions * k;
      TA_REQUIRE(rf::add(rig, rf::pose_a_deg(i), c, rf::actual_ball(rf::pose_a_deg(i), c)) == kDone);
    }
  }
  TA_REQUIRE(rf::build(rig, false) == kDone);
  rig.set(v::kArgQ, 0.0);
  TA_REQUIRE(rig.done(9836));
  TA_CHECK_EQ(rig.get(v::kCheckFigures), 4.0);  // A 30 and 60, two figures each
  // The check's figures name its own poses, 2 (A 30) and 3 (A 60); its log
  // entry the stored table's, 4 and 5.
  for (int q = 1; q <= 4; ++q) {
    rig.set(v::kArgQ, q);
    TA_REQUIRE(rig.done(9836));
    TA_CHECK(rig.get(v::kCheckFigureItem) == 2.0 || rig.get(v::kCheckFigureItem) == 3.0);
  }
  const Shown check = show(rig, rig.get(v::kLogNewest));
  TA_CHECK_EQ(check.type(), 1.0);
  TA_CHECK_EQ(check.figures(), 2.0);
  for (std::size_t k = 0; k < 2; ++k) TA_CHECK(check.figure(k, 1) == 4.0 || check.figure(k, 1) == 5.0);
  // The stored table answers its pose 4 with A = 30 (what a reader names the figure by).
  rig.set(v::kArgQ, 4.0);
  rig.set(v::kArgR, 1.0);
  TA_REQUIRE(rig.done(9834));
  TA_CHECK_EQ(rig.get(v::kPoseA), 30.0);
}
