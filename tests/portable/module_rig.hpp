// The one rig for every test that drives a Module through its registers, on
// the host (Catch2 programs) and on the Cortex-M7 (the portable tests): a
// device, a clock, a started module, writes and reads by number, a macro run
// to its end, the unlock.
//
// Contract
//  1. Heap-free. The module (tens of kilobytes, more than the Cortex-M7
//     image's 64 KiB stack should carry) and the rig's own device live in
//     static storage, in one of kRigSlots slots that a rig takes for its
//     lifetime: at most kRigSlots rigs at once in a program (a test that needs
//     two modules over one device, a restart, uses start() instead).
//  2. The device is the rig's own FlakyStorage (fakes.hpp), blank at
//     construction: a test reaches its bytes, makes it refuse or cut, through
//     storage(). A test that needs another device (a file, one shared with
//     another rig) or another clock hands it in RigOptions; so too its own
//     extra macros (module.hpp contract 6).
//  3. Every module the rig makes also has the test kit's macros (kKitMacros):
//     9990 fills #100..#199 with kSentinel, 9991 and 9992 open a session and
//     a computation of a method that is none of the built ones (what another
//     method's clear or build does to the shared arenas, method_context.hpp
//     contract 4).
//  4. put(), get() and run() return what the module answered and leave the
//     checking to the test. set(), value() and the run() of a macro that must
//     start report a failure they meet through the failure handler and go on
//     (a portable test records it; a Catch2 program installs a handler that
//     fails the test case, tests/support/catch_main.cpp), naming the line of
//     the test that called them.
//  5. run() writes #9000, steps until the module is idle (at most kMaxSteps
//     steps) and returns #9001: kDone, kError, or -1 when the command was
//     refused or the macro never ended.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <utility>

#include "fakes.hpp"
#include "portable_test.hpp"
#include "rig_failure.hpp"
#include "static_slot.hpp"
#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/hal/clock.hpp"
#include "trueaxis/hal/nv_storage.hpp"
#include "trueaxis/macros/method_context.hpp"
#include "trueaxis/macros/module.hpp"

namespace trueaxis::test {

inline constexpr double kIdle = static_cast<double>(macros::MacroState::kIdle);
inline constexpr double kBusy = static_cast<double>(macros::MacroState::kBusy);
inline constexpr double kDone = static_cast<double>(macros::MacroState::kDone);
inline constexpr double kError = static_cast<double>(macros::MacroState::kError);

// Contract 3.
inline constexpr std::uint16_t kPrefillMacro = 9990;
inline constexpr std::uint16_t kForeignSessionMacro = 9991;
inline constexpr std::uint16_t kForeignWorkMacro = 9992;
inline constexpr double kSentinel = -7.25e77;

namespace rig_detail {

// A method none of the built ones is: its own session and work types.
struct ForeignSession {
  char held = 0;
};
struct ForeignWork {
  char held = 0;
};
struct ForeignShape {
  static constexpr macros::List<macros::VarInfo> kRows{};
  using Session = ForeignSession;
  using Work = ForeignWork;
};

template <std::size_t... I>
void prefill(macros::PlatformContext& ctx, std::index_sequence<I...>) {
  (ctx.out<static_cast<std::uint16_t>(macros::var::kResultFirst + I)>(kSentinel), ...);
}
inline macros::MacroStep run_prefill(macros::PlatformContext& ctx) {
  prefill(ctx, std::make_index_sequence<macros::var::kResultLast - macros::var::kResultFirst + 1>{});
  return macros::done(core::Status::kOk);
}
inline macros::MacroStep run_foreign_session(macros::MethodContext<ForeignShape>& ctx) {
  ctx.open_session().held = 1;
  return macros::done(core::Status::kOk);
}
inline macros::MacroStep run_foreign_work(macros::MethodContext<ForeignShape>& ctx) {
  ctx.open_work().held = 1;
  return macros::done(core::Status::kOk);
}

inline constexpr macros::OutputInfo kKitOutputs[] = {{100, "kit", "", "The test kit's macros publish nothing."}};

}  // namespace rig_detail

inline constexpr macros::MacroInfo kKitMacros[] = {
    macros::macro<&rig_detail::run_prefill>(kPrefillMacro, "test_prefill", "Fills #100..#199 with the sentinel.",
                                            rig_detail::kKitOutputs),
    macros::macro<&rig_detail::run_foreign_session>(kForeignSessionMacro, "test_foreign_session",
                                                    "Opens another method's session.", rig_detail::kKitOutputs),
    macros::macro<&rig_detail::run_foreign_work>(kForeignWorkMacro, "test_foreign_work",
                                                 "Opens another method's computation.", rig_detail::kKitOutputs),
};
inline constexpr std::size_t kKitMacroCount = sizeof kKitMacros / sizeof kKitMacros[0];

// Contract 2.
struct RigOptions {
  hal::NvStorage* storage = nullptr;          // another device; nullptr: the rig's own
  hal::Clock* clock = nullptr;                // another clock; nullptr: the rig's FakeClock
  const macros::MacroInfo* macros = nullptr;  // the test's own extra macros
  std::size_t macro_count = 0;
  bool start = true;                          // false: the test calls start() itself

  RigOptions& on(hal::NvStorage& s) {
    storage = &s;
    return *this;
  }
  RigOptions& with_clock(hal::Clock& c) {
    clock = &c;
    return *this;
  }
  template <std::size_t N>
  RigOptions& with_macros(const macros::MacroInfo (&m)[N]) {
    macros = m;
    macro_count = N;
    return *this;
  }
  RigOptions& unstarted() {
    start = false;
    return *this;
  }
};

inline constexpr std::size_t kRigSlots = 3;
inline constexpr std::size_t kMaxRigMacros = 8;
inline constexpr int kMaxSteps = 100000;

namespace rig_detail {
struct Slot {
  StaticSlot<macros::Module> module;
  FlakyStorage storage;
  decltype(FlakyStorage::bytes) snapshot{};
  macros::MacroInfo macros[kMaxRigMacros + kKitMacroCount] = {};
  bool taken = false;
};
inline Slot g_slots[kRigSlots];

// A slot held for a rig's lifetime (contract 1); a member, so that it is
// given back even when the rig's constructor does not finish.
class Lease {
 public:
  explicit Lease(const Where& where) {
    for (Slot& s : g_slots) {
      if (!s.taken) {
        slot_ = &s;
        break;
      }
    }
    if (slot_ == nullptr) {
      Line what;
      what.text("more than ").uint(kRigSlots).text(" rigs at once (module_rig.hpp contract 1)");
      rig_failure(where, what);
      __builtin_trap();
    }
    slot_->taken = true;
    slot_->storage.reset();
  }
  ~Lease() {
    slot_->module.reset();
    slot_->taken = false;
  }
  Lease(const Lease&) = delete;
  Lease& operator=(const Lease&) = delete;
  Slot& slot() const { return *slot_; }

 private:
  Slot* slot_ = nullptr;
};
}  // namespace rig_detail

class ModuleRig {
 public:
  ModuleRig() : ModuleRig(RigOptions{}) {}

  explicit ModuleRig(const RigOptions& options, Where where = TA_HERE) : options_(options), lease_(where) {
    rig_detail::Slot& slot = lease_.slot();
    std::size_t n = 0;
    for (const macros::MacroInfo& m : kKitMacros) slot.macros[n++] = m;
    for (std::size_t i = 0; i < options_.macro_count && i < kMaxRigMacros; ++i) slot.macros[n++] = options_.macros[i];
    macro_count_ = n;
    if (options_.start) {
      const core::Status s = start();
      if (s != core::Status::kOk) {
        Line what;
        what.text("start() answered ").integer(static_cast<int>(s));
        rig_failure(where, what);
      }
    } else {
      make_module();
    }
  }
  ModuleRig(const ModuleRig&) = delete;
  ModuleRig& operator=(const ModuleRig&) = delete;

  macros::Module& module() { return *module_; }
  const macros::Module& module() const { return *module_; }
  // The rig's own device (contract 2), whether or not the module uses it.
  FlakyStorage& storage() { return lease_.slot().storage; }
  // A copy of the rig's own device's bytes (static: no stack), and whether
  // they are still the same.
  void snapshot() { lease_.slot().snapshot = lease_.slot().storage.bytes; }
  bool unchanged() const { return lease_.slot().snapshot == lease_.slot().storage.bytes; }
  // The same but for the measuring log's two slots (a calibration stores no
  // table and logs an entry: module.hpp contract 9).
  bool unchanged_but_log() const {
    std::size_t log_first = 0;
    std::size_t log_end = 0;
    for (std::size_t i = 0; i < macros::kRecordCount; ++i) {
      if (macros::kRecordSpecs[i].key != macros::kLogRecord.key) continue;
      log_first = macros::KeyedStore::slot_offset(macros::kRecordSpecs.data(), i, 0);
      log_end = macros::KeyedStore::slot_offset(macros::kRecordSpecs.data(), i, 2);
    }
    const auto& now = lease_.slot().storage.bytes;
    const auto& then = lease_.slot().snapshot;
    for (std::size_t k = 0; k < now.size(); ++k) {
      if ((k < log_first || k >= log_end) && now[k] != then[k]) return false;
    }
    return true;
  }
  // The newest entry of the measuring log is a refusal with `code` and the
  // gate's #9012 .. #9014 (measuring_log.hpp convention 1), the window shown
  // through #9018; true in a module without a log.
  // The log keeps the item in a byte: #9012 when it is a whole number 0 .. 255;
  // M4's change gate, whose #9012 is an angle, its step 1 .. 36 (spindle_macros.cpp).
  bool logged_refusal(core::Status code) {
    namespace v = macros::var;
    if (!macros::kHasLog) return true;
    double item = get(v::kGateItem);
    const double value = get(v::kGateValue);
    const double limit = get(v::kGateLimit);
    if (put(v::kLogSelect, get(v::kLogNewest)) != macros::AccessFault::kNone) return false;
    // spindle::change_log_step, written out: the rig builds without the spindle method too.
    if (code == core::Status::kChangeBeyondLimit && get(v::kLogMacro) == 9842.0) item = item / 10.0 + 1.0;
    const auto f32 = [](double x) { return static_cast<double>(static_cast<float>(x)); };
    return get(v::kLogType) == static_cast<double>(macros::LogType::kRefusal) && get(v::kLogStored) == 0.0 &&
           get(v::kLogFigureCount) >= 1.0 && get(v::kLogFigureFirst) == macros::kRefusalFigure &&
           get(v::kLogFigureFirst + 1) == item && get(v::kLogFigureFirst + 2) == f32(value) &&
           get(v::kLogFigureFirst + 3) == static_cast<double>(static_cast<int>(code)) &&
           get(v::kLogFigureFirst + 4) == f32(limit);
  }
  // Whether a compute macro refused with `code` logs a refusal (module.hpp
  // contract 9: a logging method's gate, or table_locked).
  static bool logs_refusal(core::Status code) {
    if (!macros::kHasLog) return false;
    bool logs = false;
    for (std::size_t m = 0; m < macros::BuiltMethods::kCount; ++m) {
      if (!macros::BuiltMethods::kLogs[m]) continue;
      logs = logs || code == core::Status::kTableLocked;
      for (const macros::GateInfo& g : macros::BuiltMethods::kGates[m]) logs = logs || g.status == code;
    }
    return logs;
  }
  // After a compute macro refused with `code`: storage unchanged, but for the
  // refusal logged when it logs one.
  bool unchanged_after(core::Status code) {
    return logs_refusal(code) ? unchanged_but_log() && logged_refusal(code) : unchanged();
  }
  hal::NvStorage& device() { return options_.storage != nullptr ? *options_.storage : lease_.slot().storage; }
  FakeClock clock;

  // A new module over the same device and clock, started: a restart.
  [[nodiscard]] core::Status start() {
    make_module();
    return module_->start();
  }

  // ---- contract 4: what the module answers -------------------------------------------------
  macros::AccessFault put(std::uint16_t n, double value) { return module_->write(n, 1, &value); }
  macros::AccessFault put(std::uint16_t first, std::uint16_t count, const double* values) {
    return module_->write(first, count, values);
  }
  macros::AccessFault put3(std::uint16_t first, const core::Vec3& v) {
    const double xyz[3] = {v.x(), v.y(), v.z()};
    return module_->write(first, 3, xyz);
  }
  macros::AccessFault read(std::uint16_t first, std::uint16_t count, double* out) {
    return module_->read(first, count, out);
  }
  // #n as the map holds it (0 for an undefined number: value()).
  double get(std::uint16_t n) const { return module_->value(n); }
  core::Vec3 get3(std::uint16_t first) const {
    return core::Vec3(get(first), get(static_cast<std::uint16_t>(first + 1)),
                      get(static_cast<std::uint16_t>(first + 2)));
  }
  // #9002 as a status code.
  core::Status code() const { return static_cast<core::Status>(static_cast<int>(get(macros::var::kError))); }
  bool busy() const { return module_->busy(); }
  void step() { module_->step(); }

  // ---- contract 4: steps that must succeed -------------------------------------------------
  void set(std::uint16_t n, double value, Where where = TA_HERE) { expect_write(put(n, value), n, where); }
  void set(std::uint16_t first, std::uint16_t count, const double* values, Where where = TA_HERE) {
    expect_write(put(first, count, values), first, where);
  }
  void set3(std::uint16_t first, const core::Vec3& v, Where where = TA_HERE) {
    expect_write(put3(first, v), first, where);
  }
  // Contract 5.
  double run(double macro, Where where = TA_HERE) {
    const macros::AccessFault f = put(macros::var::kCmd, macro);
    if (f != macros::AccessFault::kNone) {
      Line what;
      what.text("macro ").real(macro).text(": the command was refused, access fault ").integer(static_cast<int>(f));
      rig_failure(where, what);
      return -1.0;
    }
    for (int i = 0; i < kMaxSteps && module_->busy(); ++i) module_->step();
    if (module_->busy()) {
      Line what;
      what.text("macro ").real(macro).text(" still busy after ").integer(kMaxSteps).text(" steps");
      rig_failure(where, what);
      return -1.0;
    }
    return get(macros::var::kStatus);
  }
  // Runs a macro that must succeed; true when it did.
  bool done(double macro, Where where = TA_HERE) {
    const double s = run(macro, where);
    if (s == kDone) return true;
    Line what;
    what.text("macro ").real(macro).text(" ended with status ").real(s).text(", error ").integer(
        static_cast<int>(code()));
    rig_failure(where, what);
    return false;
  }
  // Runs a macro that must fail; its code (kOk when it did not fail).
  core::Status refuse(double macro, Where where = TA_HERE) {
    const double s = run(macro, where);
    if (s == kError) return code();
    Line what;
    what.text("macro ").real(macro).text(" was expected to fail; status ").real(s);
    rig_failure(where, what);
    return core::Status::kOk;
  }

  bool unlock() { return put(macros::var::kUnlock, macros::kUnlockCode) == macros::AccessFault::kNone; }
  bool lock() { return put(macros::var::kUnlock, 0.0) == macros::AccessFault::kNone; }

  // #100..#199.
  struct Results {
    double v[macros::var::kResultLast - macros::var::kResultFirst + 1];
    double operator[](std::size_t i) const { return v[i]; }
    bool operator==(const Results& o) const {
      for (std::size_t i = 0; i < sizeof v / sizeof v[0]; ++i) {
        if (!(v[i] == o.v[i])) return false;
      }
      return true;
    }
    bool operator!=(const Results& o) const { return !(*this == o); }
  };
  Results results() const {
    Results r{};
    for (std::uint16_t k = 0; k < sizeof r.v / sizeof r.v[0]; ++k) {
      r.v[k] = get(static_cast<std::uint16_t>(macros::var::kResultFirst + k));
    }
    return r;
  }

  // Contract 3.
  bool prefill(Where where = TA_HERE) { return done(kPrefillMacro, where); }
  bool open_foreign_session(Where where = TA_HERE) { return done(kForeignSessionMacro, where); }
  bool open_foreign_work(Where where = TA_HERE) { return done(kForeignWorkMacro, where); }

 private:
  void make_module() {
    hal::Clock& c = options_.clock != nullptr ? *options_.clock : clock;
    module_ = &lease_.slot().module.emplace(device(), c, lease_.slot().macros, macro_count_);
  }
  void expect_write(macros::AccessFault f, std::uint16_t n, const Where& where) {
    if (f == macros::AccessFault::kNone) return;
    Line what;
    what.text("write of #").uint(n).text(" refused, access fault ").integer(static_cast<int>(f));
    rig_failure(where, what);
  }

  RigOptions options_;
  rig_detail::Lease lease_;
  std::size_t macro_count_ = 0;
  macros::Module* module_ = nullptr;
};

}  // namespace trueaxis::test
