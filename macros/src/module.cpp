#include "trueaxis/macros/module.hpp"

#include "trueaxis/macros/record_codec.hpp"

#include <tuple>

namespace trueaxis::macros {

namespace {

double state_value(MacroState s) { return static_cast<double>(static_cast<int>(s)); }

constexpr std::size_t kEntryBytes = kVariableEntryBytes;

constexpr RecordKey record_of(Access group) {
  return group == Access::kConfig ? RecordKey::kConfig : RecordKey::kWorkOffsets;
}

static_assert(kConfigCount * kEntryBytes <= record_capacity(RecordKey::kConfig), "config record too small");
static_assert(kWorkOffsetCount * kEntryBytes <= record_capacity(RecordKey::kWorkOffsets),
              "work-offset record too small");
static_assert(kConfigCount * kEntryBytes <= kVariableRecordBytes &&
              kWorkOffsetCount * kEntryBytes <= kVariableRecordBytes);

// Slot runs of the variables cleared after every macro (kReadWrite rows), merged
// where adjacent, so clearing is a few tight loops rather than a walk of the map.
struct SlotRun {
  std::size_t first;
  std::size_t count;
};

// Slot runs of the variables cleared after every macro (kReadWrite rows), merged
// where adjacent (slots follow the platform, then each method: not map order).
constexpr std::size_t readwrite_row_count() {
  std::size_t n = 0;
  for (const VarInfo& v : kRegisterMap) n += v.access == Access::kReadWrite ? 1 : 0;
  return n;
}

// The kReadWrite rows as slot runs, sorted by slot.
constexpr std::array<SlotRun, readwrite_row_count()> readwrite_rows() {
  std::array<SlotRun, readwrite_row_count()> rows{};
  std::size_t n = 0;
  for (const VarInfo& v : kRegisterMap) {
    if (v.access == Access::kReadWrite) rows[n++] = {slot_of(v.number), v.count};
  }
  for (std::size_t i = 1; i < n; ++i) {
    for (std::size_t j = i; j > 0 && rows[j - 1].first > rows[j].first; --j) {
      const SlotRun t = rows[j];
      rows[j] = rows[j - 1];
      rows[j - 1] = t;
    }
  }
  return rows;
}
constexpr auto kReadWriteRows = readwrite_rows();

constexpr std::size_t readwrite_run_count() {
  std::size_t runs = 0;
  for (std::size_t i = 0; i < kReadWriteRows.size(); ++i) {
    const bool joins = i > 0 && kReadWriteRows[i - 1].first + kReadWriteRows[i - 1].count == kReadWriteRows[i].first;
    runs += joins ? 0 : 1;
  }
  return runs;
}

constexpr std::array<SlotRun, readwrite_run_count()> readwrite_runs() {
  std::array<SlotRun, readwrite_run_count()> runs{};
  std::size_t n = 0;
  for (const SlotRun& row : kReadWriteRows) {
    if (n > 0 && runs[n - 1].first + runs[n - 1].count == row.first) {
      runs[n - 1].count += row.count;
    } else {
      runs[n++] = row;
    }
  }
  return runs;
}
constexpr auto kReadWriteRuns = readwrite_runs();

constexpr bool readwrite_defaults_are_zero() {
  for (const VarInfo& v : kRegisterMap) {
    if (v.access == Access::kReadWrite && v.default_value != 0.0) return false;
  }
  return true;
}
static_assert(readwrite_defaults_are_zero(), "macro inputs are cleared to 0: their default must be 0");

constexpr std::size_t kResultSlot = slot_of(var::kResultFirst);

// The numbers of every variable of one persistent group, in map order.
template <std::size_t N>
constexpr std::array<std::uint16_t, N> numbers_of(Access group) {
  std::array<std::uint16_t, N> out{};
  std::size_t n = 0;
  for (const VarInfo& v : kRegisterMap) {
    if (v.access != group) continue;
    for (std::uint16_t k = 0; k < v.count; ++k) out[n++] = static_cast<std::uint16_t>(v.number + k);
  }
  return out;
}
constexpr auto kConfigNumbers = numbers_of<kConfigCount>(Access::kConfig);
constexpr auto kWorkOffsetNumbers = numbers_of<kWorkOffsetCount>(Access::kPersistent);

// The access of a defined number (callers have checked it is defined).
Access access_of(std::uint16_t number) {
  const VarInfo* info = find_var(number);
  return info != nullptr ? info->access : Access::kReadOnly;
}

}  // namespace

Module::Module(hal::NvStorage& storage, hal::Clock& clock, const MacroInfo* extra_macros, std::size_t extra_count)
    : clock_(clock),
      extra_macros_(extra_macros),
      extra_count_(extra_count),
      store_(storage, kRecordSpecs.data(), kRecordCount, store_scratch_, sizeof store_scratch_),
      call_{values_, staged_, record_, Arena(sessions_), Arena(work_), services_, store_} {
  for (const VarInfo& v : kRegisterMap) {
    for (std::uint16_t i = 0; i < v.count; ++i) values_[slot_of(v.number) + i] = v.default_value;
  }
  record_.bytes = record_bytes_;
  record_.capacity = sizeof record_bytes_;
  record_.specs = kRecordSpecs.data();
  record_.spec_count = kRecordCount;
  BuiltMethods::for_each([this](auto index, auto tag) {
    using M = typename decltype(tag)::Type;
    auto& state = std::get<typename M::State>(states_);
    state_of_[decltype(index)::value] = &state;
    if constexpr (detail::HasProvide<M>::value) M::provide(state, services_);
  });
}

core::Status Module::start() {
  // Every record that mounted is loaded even when another did not: the store
  // refuses saves only to the unread ones, so a record left unloaded here would
  // be saved back with defaults by the next write to it.
  const core::Status s = store_.mount();
  load_variables(RecordKey::kConfig);
  load_variables(RecordKey::kWorkOffsets);
  load_tables();
  load_log_summary();
  return s;
}

// Each built method's stored table: decoded in the work arena (no macro runs
// yet), then made live; a record that failed its CRC is told apart.
void Module::load_tables() {
  BuiltMethods::for_each([this](auto, auto tag) {
    using M = typename decltype(tag)::Type;
    if constexpr (detail::has_table<M>()) {
      auto& table = M::table(std::get<typename M::State>(states_));
      const std::uint8_t key = M::Table::kRecord.key;
      std::size_t length = 0;
      if (store_.load(key, record_bytes_, sizeof record_bytes_, length) == core::Status::kOk) {
        Arena work(work_);
        table.load(record_bytes_, length, work.open<typename M::Table::Type>());
      }
      if (store_.damaged(key)) table.damaged();
    }
  });
}

// Entries are looked up by number: a later map that adds variables still loads
// an older record; numbers it no longer holds in that record, and values it
// would refuse, are skipped.
void Module::load_variables(RecordKey key) {
  std::size_t length = 0;
  if (store_.load(static_cast<std::uint8_t>(key), variable_record_, sizeof variable_record_, length) !=
      core::Status::kOk) {
    return;
  }
  for (std::size_t at = 0; at + kEntryBytes <= length; at += kEntryBytes) {
    const std::uint16_t number = get_u16(variable_record_ + at);
    const double v = get_f64(variable_record_ + at + 2);
    const VarInfo* info = find_var(number);
    if (info != nullptr && is_persistent(*info) && record_of(info->access) == key &&
        check_value(*info, v) == AccessFault::kNone) {
      set(number, v);
    }
  }
}

bool Module::unlocked() const { return unlocked_ && clock_.now_us() - last_write_us_ < kUnlockIdleUs; }

std::uint64_t Module::hold_us() const {
  bool session = hold_taken_;
  for (const ClientId c : session_of_) session = session || (c != kNoClient && c == holder_);
  if (!session) return kInterfaceGraceUs;
  return static_cast<std::uint64_t>(values_[slot<var::kInterfaceIdleLimit>()]) * 1'000'000;
}

ClientId Module::holder() const {
  if (holder_ == kNoClient || busy()) return holder_;
  // A clock behind the hold's start (the contract forbids it) keeps the holder: fail closed.
  return clock_.now_us() < hold_until_us_ ? holder_ : kNoClient;
}

// Contract 8: the hold runs from now, for as long as the holder's state gives
// it; a change of #903 later moves no hold already running.
void Module::extend_hold() { hold_until_us_ = clock_.now_us() + hold_us(); }

// Contract 8: the arguments and data blocks a client wrote are its own; they
// go when another client takes over its hold that ran out (never under a
// running macro, whose end clears them anyway).
void Module::clear_inputs() {
  if (busy()) return;
  for (const SlotRun& run : kReadWriteRuns) {
    for (std::size_t k = 0; k < run.count; ++k) values_[run.first + k] = 0.0;
  }
  show_log_entry(0.0, false);
}

// Contract 8: `client` takes the interface from no one (free, or its hold
// over); the inputs of another holder whose hold ran out are not its own.
void Module::hand_over(ClientId client) {
  if (unlocked_ && unlocked_by_ != client) unlocked_ = false;  // another's unlock closes for good
  if (holder_ != kNoClient && holder_ != client) clear_inputs();
  holder_ = client;
  hold_taken_ = false;
}

// Contract 8: the interface and the client's claim on its sessions, at once.
// The inputs stay: a client that writes one variable a connection (mbpoll)
// hands its arguments on to its own next connection.
void Module::give_back(ClientId client) {
  if (holder_ == client) {
    holder_ = kNoClient;
    hold_taken_ = false;
  }
  for (ClientId& c : session_of_) c = c == client ? kNoClient : c;
}

void Module::disconnected(ClientId client) {
  give_back(client);
  if (unlocked_by_ == client) unlocked_ = false;
}

double Module::value(std::uint16_t number, ClientId client) const {
  switch (number) {
    case var::kUnlock: return unlocked() ? 1.0 : 0.0;
    case var::kUnlockCodeSetting: return 0.0;  // write-only
    case var::kInterface: {
      const ClientId h = holder();
      return h == kNoClient ? 0.0 : h == client ? 1.0 : 2.0;
    }
    case var::kUnlockBackoffLeft: {
      const std::uint64_t now = clock_.now_us();
      return now < backoff_until_us_ ? static_cast<double>((backoff_until_us_ - now + 999'999) / 1'000'000) : 0.0;
    }
    default: break;
  }
  const std::size_t slot = slot_of(number);
  return slot < kVariableCount ? values_[slot] : 0.0;
}

void Module::set(std::uint16_t number, double value) {
  values_[slot_of(number)] = value;
  if (number == var::kHomeIdentity) set_tables_home(static_cast<std::uint16_t>(value));
}

// #904 to every built method's stored table (stored_table.hpp contract 4):
// at start from the config record, and after every write of it.
void Module::set_tables_home(std::uint16_t home) {
  BuiltMethods::for_each([this, home](auto, auto tag) {
    using M = typename decltype(tag)::Type;
    if constexpr (detail::has_table<M>()) M::table(std::get<typename M::State>(states_)).set_home(home);
  });
}

AccessFault Module::do_read(std::uint16_t first, std::uint16_t count, double* out, ClientId client) {
  for (std::uint16_t i = 0; i < count; ++i) {
    if (find_var(static_cast<std::uint16_t>(first + i)) == nullptr) return fault(AccessFault::kUndefined);
  }
  for (std::uint16_t i = 0; i < count; ++i) out[i] = value(static_cast<std::uint16_t>(first + i), client);
  return AccessFault::kNone;
}

AccessFault Module::check_write(std::uint16_t number, double value, ClientId client) const {
  const VarInfo* info = find_var(number);
  if (info == nullptr) return AccessFault::kUndefined;
  switch (info->access) {
    case Access::kReadOnly:
      return AccessFault::kReadOnly;
    case Access::kUnlock:
      return check_unlock(value);
    case Access::kCommand:
      if (busy()) return AccessFault::kBusy;
      return check_value(*info, value);
    case Access::kInterface:  // contract 8: taken or given back, busy or not
      return check_value(*info, value);
    case Access::kConfig:  // contract 8: under the writer's own unlock only
      if (!unlocked() || unlocked_by_ != client) return AccessFault::kLocked;
      [[fallthrough]];
    case Access::kReadWrite:
    case Access::kPersistent:
      if (busy()) return AccessFault::kBusy;
      return check_value(*info, value);
  }
  return AccessFault::kUndefined;
}

AccessFault Module::check_unlock(double value) const {
  if (!std::isfinite(value)) return AccessFault::kNotFinite;
  if (value == 0.0) return AccessFault::kNone;  // locking is always allowed
  if (clock_.now_us() < backoff_until_us_) return AccessFault::kUnlockBackoff;
  return value == values_[slot<var::kUnlockCodeSetting>()] ? AccessFault::kNone : AccessFault::kBadUnlockCode;
}

void Module::failed_unlock() {
  at<var::kFailedUnlocks>() = at<var::kFailedUnlocks>() + 1.0;
  failed_in_row_ = failed_in_row_ < 7 ? failed_in_row_ + 1 : 7;
  const std::uint64_t backoff = std::uint64_t{1'000'000} << (failed_in_row_ - 1);
  backoff_until_us_ = clock_.now_us() + (backoff < kMaxBackoffUs ? backoff : kMaxBackoffUs);
}

// The whole record of one group (config or work offsets) with the written
// values in place, saved as that group's record alone.
AccessFault Module::save_variables(Access group, std::uint16_t first, std::uint16_t count, const double* values) {
  const std::uint16_t* numbers = group == Access::kConfig ? kConfigNumbers.data() : kWorkOffsetNumbers.data();
  const std::size_t n = group == Access::kConfig ? kConfigNumbers.size() : kWorkOffsetNumbers.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t number = numbers[i];
    const bool written = number >= first && number - first < count;
    put_u16(variable_record_ + kEntryBytes * i, number);
    // The stored value, not value(): #900 reads 0 (write-only), and a save of
    // another configuration variable must keep the unlock code.
    put_f64(variable_record_ + kEntryBytes * i + 2, written ? values[number - first] : values_[slot_of(number)]);
  }
  const core::Status s = store_.save(static_cast<std::uint8_t>(record_of(group)), variable_record_, kEntryBytes * n);
  return s == core::Status::kOk ? AccessFault::kNone : AccessFault::kStorageFailure;
}

AccessFault Module::do_write(std::uint16_t first, std::uint16_t count, const double* values, ClientId client) {
  if (unlocked_ && !unlocked()) unlocked_ = false;  // idle past kUnlockIdleUs: closed for good
  // Contract 8: a lock alone is accepted from anyone; any other write only
  // while no other client holds the interface, and some writes take it.
  const bool lock_alone = count == 1 && first == var::kUnlock && values[0] == 0.0;
  const ClientId h = holder();
  if (!lock_alone && h != kNoClient && h != client) return fault(AccessFault::kInterfaceHeld);
  bool takes = false;
  bool touches[2] = {false, false};  // config, work offsets
  for (std::uint16_t i = 0; i < count; ++i) {
    const auto number = static_cast<std::uint16_t>(first + i);
    const Access access = access_of(number);
    const AccessFault f = check_write(number, values[i], client);
    if (f == AccessFault::kBadUnlockCode) failed_unlock();
    if (f != AccessFault::kNone) return fault(f);
    takes = takes || access == Access::kReadWrite || access == Access::kCommand ||
            (access == Access::kInterface && values[i] != 0.0);
    touches[0] = touches[0] || access == Access::kConfig;
    touches[1] = touches[1] || access == Access::kPersistent;
  }
  // Storage first: if it refuses, the variables keep their old values. The two
  // groups lie thousands of numbers apart with undefined numbers between, so a
  // write that passed the checks touches at most one of them.
  if (touches[0] && save_variables(Access::kConfig, first, count, values) != AccessFault::kNone) {
    return fault(AccessFault::kStorageFailure);
  }
  if (touches[1] && save_variables(Access::kPersistent, first, count, values) != AccessFault::kNone) {
    return fault(AccessFault::kStorageFailure);
  }

  if (takes && h != client) hand_over(client);
  for (std::uint16_t i = 0; i < count; ++i) {
    const auto number = static_cast<std::uint16_t>(first + i);
    const Access access = access_of(number);
    if (access == Access::kUnlock) {
      unlocked_ = values[i] != 0.0;  // check_unlock passed: the code or 0
      if (unlocked_) {
        failed_in_row_ = 0;
        unlocked_by_ = client;
      }
      continue;
    }
    if (access == Access::kInterface) {
      if (values[i] == 0.0) {
        give_back(client);
      } else {
        hold_taken_ = true;
      }
      continue;
    }
    set(number, values[i]);
    if (number == var::kLogSelect) show_log_entry(values[i], false);
    if (number == var::kLogIndex) show_log_entry(values[i], true);
    if (access == Access::kCommand && values[i] != 0.0) {  // 0 runs nothing and changes no state
      pending_ = static_cast<std::uint16_t>(values[i]);
      runner_ = client;
      phase_ = Phase::kStart;
      at<var::kStatus>() = state_value(MacroState::kBusy);
      at<var::kError>() = 0.0;
    }
  }
  if (takes && holder_ == client) extend_hold();  // only a write that takes it holds it longer (contract 8)
  if (unlocked_by_ == client) last_write_us_ = clock_.now_us();  // contract 7: the unlock's own client's writes
  return AccessFault::kNone;
}

void Module::do_note_fault(AccessFault f) { at<var::kAccessFault>() = static_cast<double>(static_cast<int>(f)); }

MacroEntry Module::lookup(std::uint16_t number) const {
  const MacroEntry built = find_macro_entry(number);
  if (built.info != nullptr) return built;
  for (std::size_t i = 0; i < extra_count_; ++i) {
    if (extra_macros_[i].number == number) return {&extra_macros_[i], BuiltMethods::kCount};
  }
  return {nullptr, 0};
}

void Module::step() {
  if (pending_ == 0) return;
  bool first_step = false;
  if (phase_ == Phase::kStart) {
    started_us_ = clock_.now_us();
    steps_ = 0;
    running_ = lookup(pending_);
    if (running_.info == nullptr) {
      ++steps_;
      finish(core::Status::kUnknownMacro);
      return;
    }
    for (std::size_t i = 0; i < kResultSlots; ++i) staged_[i] = values_[kResultSlot + i];
    record_.staged = false;
    call_.on_success = nullptr;
    call_.refusal = {};
    call_.log_staged = false;
    committed_ = false;
    phase_ = Phase::kRunning;
    first_step = true;
  }
  ++steps_;

  if (phase_ == Phase::kRunning) {
    const bool extra = running_.method >= BuiltMethods::kCount;
    call_.own = extra ? nullptr : values_ + BuiltMethods::kSlotBase[running_.method];
    call_.state = extra ? nullptr : state_of_[running_.method];
    call_.first_step = first_step;
    const MacroStep r = running_.info->run(call_);
    if (r.more) return;
    if (r.status != core::Status::kOk) {
      refuse(r.status);
    } else if (!record_.staged) {
      publish_results();
      succeed();
    } else if (!unlocked() || unlocked_by_ != runner_) {  // stored under its own client's unlock only
      refuse(core::Status::kTableLocked);
    } else {
      phase_ = Phase::kCommitting;  // the save is a step of its own: it bounds the step
    }
    return;
  }

  if (phase_ == Phase::kLogging) {
    append_log();
    finish(logged_status_);
    return;
  }

  // Phase::kCommitting: the table first, then the results.
  if (store_.save(record_.key, record_.bytes, record_.length) != core::Status::kOk) {
    finish(core::Status::kStorageFailure);
    return;
  }
  if (record_.commit != nullptr) record_.commit(record_.table);
  committed_ = true;
  publish_results();
  succeed();
}

void Module::succeed() {
  if (kHasLog && call_.log_staged && running_.method < BuiltMethods::kCount && BuiltMethods::kLogs[running_.method]) {
    phase_ = Phase::kLogging;  // contract 9: the append is a step of its own
    logged_status_ = core::Status::kOk;
    return;
  }
  finish(core::Status::kOk);
}

// Contract 9: a logging method's compute macro refused by one of its gates, or
// its store refused as table_locked, logs a refusal (measuring_log.hpp
// convention 1) in a step of its own; any other failure logs nothing.
void Module::refuse(core::Status status) {
  const std::size_t m = running_.method;
  bool logs = kHasLog && m < BuiltMethods::kCount && BuiltMethods::kLogs[m] &&
              running_.info->number == BuiltMethods::kSessions[m].compute;
  bool gate = status == core::Status::kTableLocked;
  if (logs) {
    for (const GateInfo& g : BuiltMethods::kGates[m]) gate = gate || g.status == status;
  }
  if (!logs || !gate) {
    finish(status);
    return;
  }
  LogEntry e;
  e.type = LogType::kRefusal;
  const Refusal& why = call_.refusal;
  e.add(kRefusalFigure, why.log_item, why.value,
        static_cast<double>(static_cast<int>(status)), why.limit);
  for (std::size_t k = 0; call_.log_staged && k < call_.log.figure_count; ++k) {
    const LogFigure& f = call_.log.figures[k];
    e.add(f.kind, f.item, f.value, f.sigma, f.tolerance);
  }
  call_.log = e;
  call_.log_staged = true;
  phase_ = Phase::kLogging;
  logged_status_ = status;
}

// Measuring_log.hpp convention 5: what an entry is worth keeping, 0..3.
std::uint8_t Module::log_rank(std::uint16_t macro, LogType type, bool stored, std::uint32_t table_sequence) const {
  if (type == LogType::kRefusal || (type == LogType::kCalibration && !stored)) return 0;
  const MacroEntry entry = find_macro_entry(macro);
  const std::uint8_t key = entry.info != nullptr ? BuiltMethods::kTableRecordOf[entry.method].key : 0;
  const std::uint32_t present = key != 0 ? store_.sequence(key) : 0;
  if (present == 0 || table_sequence != present) return 1;
  return stored ? 3 : 2;
}

// Contract 9: the entry the macro logged, completed and appended (or, after its
// own method's calibration, in that entry's place: measuring_log.hpp
// convention 2), the whole log saved again as one record.
void Module::append_log() {
  if constexpr (kHasLog) {
    // Whatever becomes of this append, the calibration before it can no longer
    // be replaced (a lost entry must not let a later store or check overwrite an older one).
    const std::size_t replaceable = replaceable_method_;
    replaceable_method_ = 0;
    LogEntry e = call_.log;
    e.macro = running_.info->number;
    const double t = at<var::kLogTime>();
    e.time_s = t > 0.0 ? static_cast<std::uint32_t>(t) : clock_.wall_s();
    e.stored = committed_;
    const std::uint8_t table_key = BuiltMethods::kTableRecordOf[running_.method].key;
    e.table_sequence = table_key != 0 ? store_.sequence(table_key) : 0;
    std::size_t length = 0;
    if (store_.load(kLogRecord.key, record_bytes_, kLogBytes, length) != core::Status::kOk) {
      at<var::kLogLost>() = at<var::kLogLost>() + 1.0;
      return;
    }
    std::size_t n = log_codec::count(record_bytes_, length);
    if (n == 0 && length > 0) at<var::kLogLost>() = at<var::kLogLost>() + 1.0;  // not a log: started again
    const std::uint32_t newest = n > 0 ? log_codec::serial_at(record_bytes_, n - 1) : 0;
    const bool replace = (e.stored || e.type != LogType::kCalibration) && replaceable == running_.method + 1 &&
                         n > 0 && newest == replaceable_serial_;
    e.serial = replace ? newest : newest + 1;
    if (e.serial == 0) e.serial = 1;  // after 2^32 - 1 appends: serials no longer rise, the log starts again
    if (!replace && n == kLogEntries) {  // convention 5: the oldest of the lowest rank goes, or the new entry
      std::size_t drop = n;
      std::uint8_t lowest = log_rank(e.macro, e.type, e.stored, e.table_sequence);
      for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t rank = log_rank(log_codec::macro_at(record_bytes_, i), log_codec::type_at(record_bytes_, i),
                                           log_codec::stored_at(record_bytes_, i), log_codec::sequence_at(record_bytes_, i));
        if (rank < lowest || (rank == lowest && drop == n)) {
          lowest = rank;
          drop = i;
        }
      }
      if (drop == n) return;  // the new entry ranks below every entry held: not kept, nothing lost
      n = log_codec::remove(record_bytes_, n, drop);
    }
    length = log_codec::add(record_bytes_, n, e, replace);
    if (store_.save(kLogRecord.key, record_bytes_, length) != core::Status::kOk) {
      at<var::kLogLost>() = at<var::kLogLost>() + 1.0;
      return;
    }
    const bool calibration = e.type == LogType::kCalibration && !e.stored;
    replaceable_method_ = calibration ? running_.method + 1 : 0;
    replaceable_serial_ = e.serial;
    at<var::kLogCount>() = static_cast<double>(length / kLogEntryBytes);
    at<var::kLogNewest>() = static_cast<double>(e.serial);
  }
}

// #9016 and #9017 from the stored log.
void Module::load_log_summary() {
  if constexpr (kHasLog) {
    std::size_t length = 0;
    if (store_.load(kLogRecord.key, record_bytes_, kLogBytes, length) != core::Status::kOk) return;
    const std::size_t n = log_codec::count(record_bytes_, length);
    at<var::kLogCount>() = static_cast<double>(n);
    at<var::kLogNewest>() = n > 0 ? static_cast<double>(log_codec::serial_at(record_bytes_, n - 1)) : 0.0;
  }
}

// #9020..#9059: the entry of serial `which` (#9018), or the which-th held,
// oldest first (#9028), or zeros when the log holds none.
void Module::show_log_entry(double which, bool by_index) {
  const std::uint8_t* entry = nullptr;
  if constexpr (kHasLog) {
    std::size_t length = 0;
    if (which > 0.0 && store_.load(kLogRecord.key, record_bytes_, kLogBytes, length) == core::Status::kOk) {
      const std::size_t n = log_codec::count(record_bytes_, length);
      for (std::size_t i = 0; i < n && entry == nullptr; ++i) {
        const bool found = by_index ? static_cast<double>(i + 1) == which : log_codec::serial_at(record_bytes_, i) == which;
        if (found) entry = record_bytes_ + i * kLogEntryBytes;
      }
    }
  }
  static_assert(var::kLogFigureCount == var::kLogSerial + 7, "#9020..#9027 are one run of slots");
  log_codec::window(entry, &at<var::kLogSerial>(), &at<var::kLogFigureFirst>(), var::kLogFigureValues);
}

// Contract 8: a clear macro that succeeded opens its runner's session of its
// method; the method's compute, compute_also or check macro that succeeded
// closes it (a method without them has 0 there, which no macro is).
void Module::note_session(core::Status status) {
  const std::size_t m = running_.method;
  if (status != core::Status::kOk || running_.info == nullptr || m >= BuiltMethods::kCount) return;
  const std::uint16_t number = running_.info->number;
  const SessionInfo& session = BuiltMethods::kSessions[m];
  if (session.capacity > 0 && number == session.clear) {
    if (BuiltMethods::kSessionInArena[m]) {  // the arena's other sessions are gone, and their claims
      for (std::size_t k = 0; k < BuiltMethods::kCount; ++k) {
        if (BuiltMethods::kSessionInArena[k]) session_of_[k] = kNoClient;
      }
    }
    session_of_[m] = holder_ == runner_ ? runner_ : kNoClient;  // not for a runner that gave it back
  } else if (number == session.compute || number == session.compute_also || number == BuiltMethods::kChecks[m].macro) {
    session_of_[m] = kNoClient;
  }
}

void Module::publish_results() {
  for (std::size_t i = 0; i < kResultSlots; ++i) values_[kResultSlot + i] = staged_[i];
}

void Module::finish(core::Status status) {
  const bool ok = status == core::Status::kOk;
  if (ok && call_.on_success != nullptr) *call_.on_success = true;
  call_.on_success = nullptr;
  at<var::kStatus>() = state_value(ok ? MacroState::kDone : MacroState::kError);
  at<var::kError>() = static_cast<double>(static_cast<int>(status));
  at<var::kDoneCount>() = at<var::kDoneCount>() + 1.0;
  at<var::kRunTime>() = static_cast<double>(clock_.now_us() - started_us_);
  note_session(status);
  if (holder_ == runner_) extend_hold();  // contract 8: the runner's hold counts from its macro's end
  at<var::kStepCount>() = static_cast<double>(steps_);
  const Refusal refused = ok ? Refusal{} : call_.refusal;  // method_context.hpp contract 8
  at<var::kGateItem>() = refused.item;
  at<var::kGateValue>() = refused.value;
  at<var::kGateLimit>() = refused.limit;  // call_.refusal is cleared when the next macro starts
  for (const SlotRun& run : kReadWriteRuns) {
    for (std::size_t k = 0; k < run.count; ++k) values_[run.first + k] = 0.0;
  }
  show_log_entry(0.0, false);  // #9018 and #9028 cleared: no entry shown
  record_.staged = false;
  record_.commit = nullptr;
  record_.table = nullptr;
  running_ = {nullptr, 0};
  phase_ = Phase::kStart;
  pending_ = 0;
}

}  // namespace trueaxis::macros
