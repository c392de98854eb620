#include "trueaxis/macros/module.hpp"

namespace trueaxis::macros {

namespace {

double state_value(MacroState s) { return static_cast<double>(static_cast<int>(s)); }

// Calls f(number) for every defined result variable (#100..#199).
template <typename F>
void for_each_result(F f) {
  for (const VarInfo& v : kRegisterMap) {
    if (v.number < var::kResultFirst || v.number > var::kResultLast) continue;
    for (std::uint16_t k = 0; k < v.count; ++k) f(static_cast<std::uint16_t>(v.number + k));
  }
}

}  // namespace

Module::Module(hal::NvStorage& storage, hal::Clock& clock) : store_(storage), clock_(clock) {
  for (const VarInfo& v : kRegisterMap) {
    for (std::uint16_t i = 0; i < v.count; ++i) values_[slot_of(static_cast<std::uint16_t>(v.number + i))] = v.default_value;
  }
}

core::Status Module::start() {
  std::size_t count = 0;
  const core::Status s = store_.load(entries_, kPersistentCount, count);
  for (std::size_t i = 0; i < count; ++i) {
    const VarInfo* info = find_var(entries_[i].number);
    if (info != nullptr && is_persistent(*info) && check_value(*info, entries_[i].value) == AccessFault::kNone) {
      set(entries_[i].number, entries_[i].value);
    }
  }
  return s;
}

double Module::value(std::uint16_t number) const {
  if (number == var::kUnlock) return unlocked_ ? 1.0 : 0.0;
  const std::size_t slot = slot_of(number);
  return slot < kVariableCount ? values_[slot] : 0.0;
}

void Module::set(std::uint16_t number, double value) { values_[slot_of(number)] = value; }

AccessFault Module::do_read(std::uint16_t first, std::uint16_t count, double* out) {
  for (std::uint16_t i = 0; i < count; ++i) {
    if (find_var(static_cast<std::uint16_t>(first + i)) == nullptr) return fault(AccessFault::kUndefined);
  }
  for (std::uint16_t i = 0; i < count; ++i) out[i] = value(static_cast<std::uint16_t>(first + i));
  return AccessFault::kNone;
}

AccessFault Module::check_write(std::uint16_t number, double value) const {
  const VarInfo* info = find_var(number);
  if (info == nullptr) return AccessFault::kUndefined;
  switch (info->access) {
    case Access::kReadOnly:
      return AccessFault::kReadOnly;
    case Access::kUnlock:
      if (!std::isfinite(value)) return AccessFault::kNotFinite;
      return (value == 0.0 || value == kUnlockCode) ? AccessFault::kNone : AccessFault::kBadUnlockCode;
    case Access::kCommand:
      if (busy()) return AccessFault::kBusy;
      return check_value(*info, value);
    case Access::kConfig:
      if (!unlocked_) return AccessFault::kLocked;
      [[fallthrough]];
    case Access::kReadWrite:
    case Access::kPersistent:
      if (busy()) return AccessFault::kBusy;
      return check_value(*info, value);
  }
  return AccessFault::kUndefined;
}

AccessFault Module::do_write(std::uint16_t first, std::uint16_t count, const double* values) {
  bool touches_storage = false;
  for (std::uint16_t i = 0; i < count; ++i) {
    const std::uint16_t number = static_cast<std::uint16_t>(first + i);
    const AccessFault f = check_write(number, values[i]);
    if (f != AccessFault::kNone) return fault(f);
    const VarInfo* info = find_var(number);
    touches_storage = touches_storage || (info != nullptr && is_persistent(*info));
  }

  if (touches_storage) {
    // Storage first: if it refuses, the variables keep their old values.
    std::size_t n = 0;
    for (const VarInfo& v : kRegisterMap) {
      if (!is_persistent(v)) continue;
      for (std::uint16_t k = 0; k < v.count; ++k) {
        const std::uint16_t number = static_cast<std::uint16_t>(v.number + k);
        const bool written = number >= first && number - first < count;
        entries_[n++] = {number, written ? values[number - first] : value(number)};
      }
    }
    if (store_.save(entries_, n) != core::Status::kOk) return fault(AccessFault::kStorageFailure);
  }

  for (std::uint16_t i = 0; i < count; ++i) {
    const std::uint16_t number = static_cast<std::uint16_t>(first + i);
    const VarInfo* info = find_var(number);
    const Access access = info != nullptr ? info->access : Access::kReadOnly;
    if (access == Access::kUnlock) {
      unlocked_ = values[i] == kUnlockCode;
      continue;
    }
    set(number, values[i]);
    if (access == Access::kCommand && values[i] != 0.0) {  // 0 runs nothing and changes no state
      pending_ = static_cast<std::uint16_t>(values[i]);
      set(var::kStatus, state_value(MacroState::kBusy));
      set(var::kError, 0.0);
    }
  }
  return AccessFault::kNone;
}

void Module::do_note_fault(AccessFault f) { set(var::kAccessFault, static_cast<double>(static_cast<int>(f))); }

void Module::step() {
  if (pending_ == 0) return;
  const std::uint64_t started_us = clock_.now_us();
  const MacroInfo* macro = find_macro(pending_);
  core::Status status = core::Status::kUnknownMacro;
  if (macro != nullptr) {
    for_each_result([this](std::uint16_t number) { staged_[number - var::kResultFirst] = value(number); });
    MacroContext ctx(values_, staged_);
    status = macro->run(ctx);
    if (status == core::Status::kOk) {
      for_each_result([this](std::uint16_t number) { set(number, staged_[number - var::kResultFirst]); });
    }
  }
  finish(status, started_us);
}

void Module::finish(core::Status status, std::uint64_t started_us) {
  const bool ok = status == core::Status::kOk;
  set(var::kStatus, state_value(ok ? MacroState::kDone : MacroState::kError));
  set(var::kError, static_cast<double>(static_cast<int>(status)));
  set(var::kDoneCount, value(var::kDoneCount) + 1.0);
  set(var::kRunTime, static_cast<double>(clock_.now_us() - started_us));
  std::size_t slot = 0;  // walk the slots with the table instead of looking each one up
  for (const VarInfo& v : kRegisterMap) {
    if (v.access == Access::kReadWrite) {
      for (std::uint16_t k = 0; k < v.count; ++k) values_[slot + k] = v.default_value;
    }
    slot += v.count;
  }
  pending_ = 0;
}

}  // namespace trueaxis::macros
