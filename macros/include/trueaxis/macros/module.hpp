// The trueaxis module as a controller sees it: the variables of the register map,
// the handshake, the macros of the built methods, their state, the shared
// arenas and the persistent records.
//
// Contract
//  1. Owned by main, handed a NvStorage and a Clock; holds every variable in a
//     fixed array. No allocation, no exceptions, no clock but the one handed in.
//     Its size is the sum of the built methods' states and tables plus the two
//     shared arenas (method.hpp convention 3), not of every method's worst case.
//  2. start() mounts the keyed store (keyed_store.hpp) and loads the
//     configuration and work-offset records, or keeps the map's defaults when
//     there are none, then each built method's stored table. Call it once
//     before anything else.
//  3. Writing a macro number to #9000 makes the module busy (status 1). Each
//     step(), called from the controller's background task, does a bounded
//     amount of work: at most kStepBoundInstructions instructions on a
//     Cortex-M7 (measured by tests/target/bench_steps.cpp for every macro). A
//     macro that needs more stays busy over several steps; a macro that stages
//     a table commits it in a step of its own. Then status is 2 (done) or 3
//     (error) with the code in #9002, #9003 has grown by one and #9008 holds
//     the number of steps taken. Arguments #1..#26 and the methods' data
//     blocks (the point list) are cleared to 0 after every macro. A macro
//     number no built method has fails with kUnknownMacro (400).
//  4. While busy, the holder's writes to #9000 and to any macro input
//     (arguments, data blocks, work offsets, configuration) are refused with
//     kBusy (another client's with kInterfaceHeld first, contract 8).
//  5. Persistence is per record: configuration (#500..#999) and work offsets
//     are two records, each calibration table one more (records.hpp). A write
//     to a persistent variable saves only its own record, and reaches storage
//     before it reaches the variables; a storage failure refuses the write and
//     changes nothing. A table a macro staged is saved only while unlocked
//     (else kTableLocked), before the macro's results are published; a failed
//     save fails the macro with kStorageFailure and publishes nothing.
//  6. Extra macros (an integrator's own, or a test's) may be handed in; they
//     are looked up after the built methods' macros, see the platform alone
//     (method_context.hpp PlatformContext) and share their contract.
//  7. Access control. #9004 takes the code in #900 (a persistent
//     configuration variable, default kUnlockCode = 2718, published for
//     commissioning only; it reads 0) or 0. A right code unlocks; 0 locks. A
//     wrong code is refused (kBadUnlockCode), counted in #9010, and makes
//     #9004 refuse every code for a back-off of 2^(k-1) s after the k-th wrong
//     code in a row (at most 64 s; kUnlockBackoff, Modbus 06); a right code
//     resets k; #9011 reads the seconds of back-off left. An unlock closes by
//     itself kUnlockIdleUs after its client's last write that succeeded, when the
//     transport calls lock() or disconnected() for the client that opened it,
//     and when another client takes the macro interface (contract 8). The
//     clock is the one handed in.
//  8. One client at a time: the macro interface. The module grants it to one
//     client (the ClientId each request names, variable_access.hpp; the
//     controller's own calls name kLocalClient) at a time, so that two macro
//     sequences never mix their arguments or sessions.
//     - Taking it: a write of an argument (#1..#26), a data block, #9015,
//       #9018 (the kReadWrite rows), #9000, or #9009 = 1 takes it when it is
//       free. A write of a work offset, a configuration variable or #9004
//       takes nothing: it is accepted from any client while no other client
//       holds the interface. A lock alone (#9004 = 0) is always accepted.
//     - Holding it: the holder keeps it while its macro runs, however long;
//       after that, kInterfaceGraceUs (2 s, time to read its results) after
//       its macro's end or its last write that took it; while it has a
//       session of its own open, or after it wrote #9009 = 1, up to the idle
//       limit #903 (interface_idle_s, 5..600 s, default 30) after them. A
//       write that takes nothing holds it no longer; a hold that ended stays
//       ended (the deadline is set at each activity, so a later #903 changes
//       no hold). A client's session is open from the end of its method's
//       clear macro (SessionInfo::clear, with success) until that method's
//       compute, compute_also or check macro ends with success (a refused
//       compute keeps the session for a retry), another client clears it, a
//       clear of another method whose session shares the session arena
//       replaces it, or the client gives the interface back or disconnects.
//     - Changing hands: when a client takes over another's hold that ran out,
//       the arguments and data blocks the other left are cleared, unless a
//       macro runs (its end clears them). A client that gave the interface
//       back or disconnected leaves them (a client that writes one variable a
//       connection, as mbpoll does, hands them to its own next connection).
//     - Giving it back: #9009 = 0, or the transport calls disconnected(): at
//       once, with the client's claim on its sessions (their data stay).
//     - Another client's write meanwhile, of any kind but the lock alone, is
//       refused with kInterfaceHeld (Modbus 06) and changes nothing. Reads stay
//       open to all; #9009 reads 0 when the interface is free, 1 to its
//       holder, 2 to any other client.
//     - Unlocks: a configuration write is taken only under the writer's own
//       unlock; a client that takes the interface closes another's unlock; a
//       table a macro stages is stored only under the unlock of the client that
//       started the macro.
//  9. The measuring log (measuring_log.hpp), in a module with a method that
//     logs. A macro of such a method that logged an entry and ends with kOk
//     appends it in a step of its own, after its table's commit and before
//     done; so does its compute macro refused by one of the method's gates or
//     as table_locked, as a refusal, before its error. A storage failure
//     loses the entry (#9019 counts it), not the macro. A full log keeps what
//     matters (measuring_log.hpp convention 5). #9016 and #9017 tell what
//     the log holds; #9018 (a serial) or #9028 (the k-th entry held, oldest
//     first), written with the macro interface like an argument, shows an
//     entry in #9020..#9059.
#pragma once

#include <cstdint>
#include <tuple>

#include "trueaxis/core/status.hpp"
#include "trueaxis/hal/clock.hpp"
#include "trueaxis/hal/nv_storage.hpp"
#include "trueaxis/macros/arena.hpp"
#include "trueaxis/macros/keyed_store.hpp"
#include "trueaxis/macros/method_context.hpp"
#include "trueaxis/macros/records.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/services.hpp"
#include "trueaxis/macros/variable_access.hpp"

namespace trueaxis::macros {

class Module final : public VariableAccess {
 public:
  // The longest step() of any macro on the Cortex-M7 (instructions, QEMU
  // mps2-an500 -icount; tests/target/bench_steps.cpp prints each macro's).
  static constexpr std::uint32_t kStepBoundInstructions = 130000;

  Module(hal::NvStorage& storage, hal::Clock& clock, const MacroInfo* extra_macros = nullptr,
         std::size_t extra_count = 0);

  // kOk, or kStorageFailure when a record could not be read: the records that
  // could are loaded; the unread ones keep the map's defaults, and writes to
  // them are refused (kStorageFailure) until a later start() reads them.
  [[nodiscard]] core::Status start();

  // Does one bounded piece of the pending macro, if any.
  void step();

  // Contract 7: an unlock closes this long after the last successful write.
  static constexpr std::uint64_t kUnlockIdleUs = 300'000'000;
  static constexpr std::uint64_t kMaxBackoffUs = 64'000'000;
  // Contract 8: a holder without a session keeps the macro interface this
  // long after its macro's end or its last write; with one, #903 seconds.
  static constexpr std::uint64_t kInterfaceGraceUs = 2'000'000;

  bool busy() const { return pending_ != 0; }
  // True while unlocked (and not yet idle past kUnlockIdleUs).
  bool unlocked() const;
  // Contract 7: closes an unlock (a transport calls it when the connection
  // that opened the unlock closes).
  void lock() { unlocked_ = false; }
  // Contracts 7 and 8: the transport's client went away (its connection
  // closed): the interface it held is free and the unlock it opened closes.
  void disconnected(ClientId client);
  // Contract 8: who holds the macro interface now (kNoClient when free).
  ClientId holder() const;
  // Contract 8: how long the holder keeps it after its last activity (the
  // grace, or #903 with a session or #9009 = 1), in microseconds.
  std::uint64_t hold_us() const;

  // The value of #number as `client` reads it (only #9009 depends on who
  // asks); 0 for a number the map does not define.
  double value(std::uint16_t number, ClientId client = kLocalClient) const;

  // A built method's state, for its direct calls from the controller's
  // real-time task (e.g. rigidity::compensation_rad(module.state<rigidity::Method>(), ...)):
  // const, and safe beside step() through each method's stored table.
  template <typename M>
  const typename M::State& state() const {
    return std::get<typename M::State>(states_);
  }

  // A built method's calibration session while it holds the session arena,
  // else nullptr (for tests and diagnostics).
  template <typename M>
  const typename M::Session* session() const {
    return arena_find<typename M::Session>(sessions_);
  }

  // The arenas' sizes, for the size report.
  static constexpr std::size_t kSessionArenaBytes = BuiltMethods::kSessionBytes;
  static constexpr std::size_t kWorkArenaBytes = BuiltMethods::kWorkBytes;

 private:
  enum class Phase : std::uint8_t { kStart, kRunning, kCommitting, kLogging };

  AccessFault do_read(std::uint16_t first, std::uint16_t count, double* out, ClientId client) override;
  AccessFault do_write(std::uint16_t first, std::uint16_t count, const double* values, ClientId client) override;
  void do_note_fault(AccessFault f) override;

  AccessFault check_write(std::uint16_t number, double value, ClientId client) const;
  void give_back(ClientId client);
  void hand_over(ClientId client);
  void extend_hold();
  void clear_inputs();
  void note_session(core::Status status);
  AccessFault check_unlock(double value) const;
  void failed_unlock();
  AccessFault save_variables(Access group, std::uint16_t first, std::uint16_t count, const double* values);
  void load_variables(RecordKey key);
  void load_tables();
  MacroEntry lookup(std::uint16_t number) const;
  void set(std::uint16_t number, double value);
  void set_tables_home(std::uint16_t home);
  // The module's own variables by a number known at compile time (no search).
  template <std::uint16_t N>
  double& at() {
    return values_[slot<N>()];
  }
  void publish_results();
  void succeed();  // done, after the log's step when the macro logged (contract 9)
  void refuse(core::Status status);  // failed, after the log's step when it logs a refusal (contract 9)
  std::uint8_t log_rank(std::uint16_t macro, LogType type, bool stored, std::uint32_t table_sequence) const;
  void finish(core::Status status);
  void append_log();
  void load_log_summary();
  void show_log_entry(double which, bool by_index);

  using SessionStorage = ArenaStorage<BuiltMethods::kSessionBytes, BuiltMethods::kSessionAlign>;
  using WorkStorage = ArenaStorage<BuiltMethods::kWorkBytes, BuiltMethods::kWorkAlign>;
  // The table records a macro stages, and the log's record while it is appended or read.
  static constexpr std::size_t kLogBufferBytes = kHasLog ? kLogBytes : 0;
  static constexpr std::size_t kRecordBufferBytes =
      kMaxRecordPayloadBytes > kLogBufferBytes ? kMaxRecordPayloadBytes : (kLogBufferBytes > 0 ? kLogBufferBytes : 1);

  hal::Clock& clock_;
  const MacroInfo* extra_macros_;
  std::size_t extra_count_;
  std::uint8_t store_scratch_[kStoreScratchBytes] = {};
  KeyedStore store_;
  double values_[kVariableCount] = {};
  double staged_[kResultSlots] = {};
  std::uint8_t variable_record_[kVariableRecordBytes] = {};
  std::uint8_t record_bytes_[kRecordBufferBytes] = {};
  RecordStage record_;
  BuiltMethods::States states_;
  void* state_of_[BuiltMethods::kCount > 0 ? BuiltMethods::kCount : 1] = {};
  SessionStorage sessions_;
  WorkStorage work_;
  Services services_;
  MacroCall call_;
  MacroEntry running_{nullptr, 0};
  std::uint64_t started_us_ = 0;
  std::uint32_t steps_ = 0;
  std::uint16_t pending_ = 0;
  Phase phase_ = Phase::kStart;
  bool unlocked_ = false;
  std::uint64_t last_write_us_ = 0;   // contract 7's idle clock
  std::uint64_t backoff_until_us_ = 0;
  std::uint32_t failed_in_row_ = 0;
  ClientId unlocked_by_ = kNoClient;  // contract 7: whose unlock is open
  ClientId holder_ = kNoClient;       // contract 8
  bool hold_taken_ = false;           // the holder wrote #9009 = 1
  ClientId runner_ = kNoClient;       // who wrote the running macro's number
  std::uint64_t hold_until_us_ = 0;   // the holder's hold ends here (its last activity + hold_us())
  // Contract 8: whose session of each built method is open (kNoClient: none).
  ClientId session_of_[BuiltMethods::kCount > 0 ? BuiltMethods::kCount : 1] = {};
  bool committed_ = false;                 // the running macro stored its table
  core::Status logged_status_ = core::Status::kOk;  // how the macro ends after its log's step
  std::size_t replaceable_method_ = 0;     // measuring_log.hpp convention 2: method + 1, 0 none
  std::uint32_t replaceable_serial_ = 0;   // that calibration's entry
};

}  // namespace trueaxis::macros
