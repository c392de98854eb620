// What a handler sees while it runs: typed access to the platform's variables
// and to its own method's, the staged results, its method's calibration
// session and work in the shared arenas, the record it may stage, and the
// services other methods offer. Nothing of any other method.
//
// Contract
//  1. A method describes what its handlers see in a Shape (method.hpp):
//       static constexpr List<VarInfo> kRows;  its own rows of the map
//       using Session = ...;                   its calibration session, or NoSession
//       using Work = ...;                      its builder and last computation, or NoWork
//     and its handlers take MethodContext<Shape>& (method.hpp calls it Context).
//  2. in<N>() reads #N; out<N>(v) stages result #N. Both take the number as a
//     template argument: a number neither the platform nor the method's own
//     rows define, or an out<N> outside #100..#199, does not compile. The slot
//     is computed at compile time from the platform's rows and the method's
//     own (platform_map.hpp convention 7), so a method compiles alone.
//  3. in_block<First>(k) reads element k of the method's block that starts at
//     #First (0 for k past the block's end).
//  4. session() is the method's session in the shared session arena: the one
//     it holds, or a new empty one when no method has opened a session since
//     start; nullptr when another method's session holds the arena (the
//     handler then answers kSessionClosed). open_session() always opens a new
//     empty one, closing another method's: only the method's clear macro calls
//     it. Likewise work() / open_work() in the work arena: open_work() at the
//     first step of a computation; work() returns nullptr once another
//     method's computation (or start()'s decoding) has used the arena since.
//  5. stage_table(table, t) encodes t into the record buffer as the table's
//     record; the module saves it when the macro ends with kOk, then makes t
//     live (stored_table.hpp). kTableInvalid when t does not encode or its
//     record is too small. stage_record(key, length) is the raw form for
//     integrators' own macros (nullptr when length exceeds the key's capacity).
//     One record per macro run; staging again replaces it.
//  6. load_record reads a key's newest stored record (the not-hot path).
//  7. set_on_success(flag): the module sets `flag` true when this macro ends
//     with kOk, after its record was committed, and leaves it alone on any
//     other end: a method's "the last computation succeeded" (9834, 9824,
//     9826, 9844, 9845 with R = 0) follows the macro's own outcome.
//  8. refuse(status, item, value, limit): a gate's refusal (gates.hpp): ends
//     the macro with `status` and has the module publish item, value and
//     limit in #9012 .. #9014 (which read 0 after any other end). Results
//     and tables stay as they were, as on every failure.
//  9. log(entry): the measuring log's entry of this run (measuring_log.hpp):
//     its type, verdict and figures; the module adds serial, time, macro,
//     stored and table sequence, and appends it when the macro ends with kOk,
//     in a step of its own, if the method logs (its kLogFigures). Logging
//     again replaces it.
//  No allocation, no exceptions.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "trueaxis/core/status.hpp"
#include "trueaxis/core/types.hpp"
#include "trueaxis/macros/arena.hpp"
#include "trueaxis/macros/keyed_store.hpp"
#include "trueaxis/macros/list.hpp"
#include "trueaxis/macros/macro_info.hpp"
#include "trueaxis/macros/measuring_log.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/services.hpp"
#include "trueaxis/macros/stored_table.hpp"

namespace trueaxis::macros {

// Shapes without a session or work (contract 1).
struct NoSession {};
struct NoWork {};

// What a gate refused (contract 8): #9012 .. #9014.
// The measuring log keeps the item in a byte (measuring_log.hpp convention 1):
// log_item, which is the item itself when it is a whole number 0 .. 255 and
// otherwise what the method says (M4's change gate: the angle's step).
struct Refusal {
  double item = 0.0;
  double value = 0.0;
  double limit = 0.0;
  std::uint8_t log_item = 0;
};

// A record a macro staged, waiting for the macro to succeed; the bytes are the
// module's buffer, as large as the largest record of the built methods.
struct RecordStage {
  std::uint8_t* bytes = nullptr;
  std::size_t capacity = 0;
  const RecordSpec* specs = nullptr;  // the module's record list, for capacities
  std::size_t spec_count = 0;
  std::uint8_t key = 0;
  std::size_t length = 0;
  bool staged = false;
  void* table = nullptr;               // the StoredTable to commit into, or nullptr (raw)
  void (*commit)(void*) = nullptr;
};

// Everything the module hands a handler (macro_info.hpp contract 5): made once
// with the module; own, state and first_step are set for each call.
struct MacroCall {
  const double* platform;  // the platform's slots (platform_map.hpp convention 7)
  double* staged;          // #100..#199
  RecordStage& record;
  Arena sessions;
  Arena work;
  const Services& services;
  KeyedStore& store;
  bool* on_success = nullptr;  // contract 7
  Refusal refusal{};           // contract 8
  LogEntry log{};              // contract 9
  bool log_staged = false;
  const double* own = nullptr;  // the running method's own slots; nullptr for an extra macro
  void* state = nullptr;        // the running method's State; nullptr for an extra macro
  bool first_step = false;
};

namespace detail {
constexpr std::size_t slot_in_list(List<VarInfo> rows, std::uint16_t number) {
  std::size_t slot = 0;
  for (const VarInfo& v : rows) {
    if (number >= v.number && number - v.number < v.count) return slot + (number - v.number);
    slot += v.count;
  }
  return kNoSlot;
}
constexpr const VarInfo* row_in_list(List<VarInfo> rows, std::uint16_t number) {
  for (const VarInfo& v : rows) {
    if (number >= v.number && number - v.number < v.count) return &v;
  }
  return nullptr;
}
}  // namespace detail

template <typename Shape>
class MethodContext {
 public:
  using Session = typename Shape::Session;
  using Work = typename Shape::Work;

  explicit MethodContext(MacroCall& call)
      : call_(call), platform_(call.platform), own_(call.own), staged_(call.staged) {}

  template <std::uint16_t N>
  double in() const {
    constexpr std::size_t p = platform_slot(N);
    if constexpr (p != kNoSlot) {
      return platform_[p];
    } else {
      constexpr std::size_t s = detail::slot_in_list(Shape::kRows, N);
      static_assert(s != kNoSlot, "neither the platform nor this method defines this variable number");
      return own_[s];
    }
  }

  template <std::uint16_t First>
  double in_block(std::size_t k) const {
    constexpr const VarInfo* row = detail::row_in_list(Shape::kRows, First);
    static_assert(row != nullptr && row->number == First, "in_block takes the first number of one of the method's blocks");
    constexpr std::size_t first = detail::slot_in_list(Shape::kRows, First);
    constexpr std::size_t count = row->count;
    return k < count ? own_[first + k] : 0.0;
  }

  template <std::uint16_t N>
  void out(double value) {
    static_assert(N >= var::kResultFirst && N <= var::kResultLast, "results are #100..#199");
    staged_[N - var::kResultFirst] = value;
  }

  // Result #First + k of a run of Count results (k >= Count writes nothing).
  template <std::uint16_t First, std::size_t Count>
  void out_at(std::size_t k, double value) {
    static_assert(First >= var::kResultFirst && First + Count - 1 <= var::kResultLast, "results are #100..#199");
    if (k < Count) staged_[First - var::kResultFirst + k] = value;
  }

  // Results #X..#X+2 from a vector, each times `scale` (a unit conversion).
  template <std::uint16_t X>
  void out3(const core::Vec3& v, double scale = 1.0) {
    out<X>(v.x() * scale);
    out<X + 1>(v.y() * scale);
    out<X + 2>(v.z() * scale);
  }

  bool first_step() const { return call_.first_step; }
  const Services& services() const { return call_.services; }

  // Contract 4.
  Session* session() {
    static_assert(!std::is_same<Session, NoSession>::value, "this method has no calibration session");
    if (Session* s = call_.sessions.template find<Session>()) return s;
    return call_.sessions.empty() ? &call_.sessions.template open<Session>() : nullptr;
  }
  Session& open_session() {
    static_assert(!std::is_same<Session, NoSession>::value, "this method has no calibration session");
    return call_.sessions.template open<Session>();
  }
  Work* work() {
    static_assert(!std::is_same<Work, NoWork>::value, "this method has no work");
    return call_.work.template find<Work>();
  }
  Work& open_work() {
    static_assert(!std::is_same<Work, NoWork>::value, "this method has no work");
    return call_.work.template open<Work>();
  }

  // Contract 5.
  template <typename Spec>
  [[nodiscard]] core::Status stage_table(StoredTable<Spec>& table, const typename Spec::Type& t) {
    const std::size_t length = Spec::bytes(t);
    if (length > Spec::kRecord.capacity_bytes || length > call_.record.capacity) return core::Status::kTableInvalid;
    if (Spec::encode(t, call_.record.bytes, length) == 0) return core::Status::kTableInvalid;
    RecordStage& r = call_.record;
    r.key = Spec::kRecord.key;
    r.length = length;
    r.staged = true;
    table.stage(t);
    r.table = &table;
    r.commit = [](void* p) { static_cast<StoredTable<Spec>*>(p)->commit(); };
    return core::Status::kOk;
  }

  std::uint8_t* stage_record(std::uint8_t key, std::size_t length) {
    RecordStage& r = call_.record;
    std::size_t capacity = 0;
    for (std::size_t i = 0; i < r.spec_count; ++i) {
      if (r.specs[i].key == key) capacity = r.specs[i].capacity_bytes;
    }
    if (length > capacity || length > r.capacity) return nullptr;
    r.key = key;
    r.length = length;
    r.staged = true;
    r.table = nullptr;
    r.commit = nullptr;
    return r.bytes;
  }

  // Contract 7.
  void set_on_success(bool& flag) { call_.on_success = &flag; }

  // Contract 9.
  void log(const LogEntry& entry) {
    call_.log = entry;
    call_.log_staged = true;
  }

  // Contract 8.
  MacroStep refuse(core::Status status, double item, double value, double limit) {
    const bool whole = item >= 0.0 && item <= 255.0 && item == static_cast<double>(static_cast<int>(item));
    return refuse(status, item, value, limit, whole ? static_cast<std::uint8_t>(item) : 0);
  }
  // The same, naming the item the measuring log keeps when #9012's does not fit its byte.
  MacroStep refuse(core::Status status, double item, double value, double limit, std::uint8_t log_item) {
    call_.refusal = {item, value, limit, log_item};
    return done(status);
  }

  [[nodiscard]] core::Status load_record(std::uint8_t key, std::uint8_t* out, std::size_t capacity,
                                         std::size_t& length) {
    return call_.store.load(key, out, capacity, length);
  }

 private:
  MacroCall& call_;
  const double* platform_;
  const double* own_;
  double* staged_;
};

// The platform alone: integrators' own macros (Module's extra macros) see the
// platform's variables and nothing of any method.
struct PlatformShape {
  static constexpr List<VarInfo> kRows{};
  using Session = NoSession;
  using Work = NoWork;
};
using PlatformContext = MethodContext<PlatformShape>;

namespace detail {
template <typename F>
struct HandlerOf;
template <typename Shape, typename State>
struct HandlerOf<MacroStep (*)(MethodContext<Shape>&, State&)> {
  using Context = MethodContext<Shape>;
  using StateType = State;
  static constexpr bool kHasState = true;
};
template <typename Shape>
struct HandlerOf<MacroStep (*)(MethodContext<Shape>&)> {
  using Context = MethodContext<Shape>;
  static constexpr bool kHasState = false;
};
}  // namespace detail

// macro_info.hpp contract 5: the thunk of one handler.
template <auto Handler>
MacroStep thunk(MacroCall& call) {
  using H = detail::HandlerOf<decltype(Handler)>;
  typename H::Context ctx(call);
  if constexpr (H::kHasState) {
    return Handler(ctx, *static_cast<typename H::StateType*>(call.state));
  } else {
    return Handler(ctx);
  }
}

template <auto Handler, std::size_t NI, std::size_t NO>
constexpr MacroInfo macro(std::uint16_t number, const char* name, const char* description,
                          const InputRef (&inputs)[NI], const OutputInfo (&outputs)[NO]) {
  return {number, &thunk<Handler>, name, description, inputs, NI, outputs, NO};
}

template <auto Handler, std::size_t NO>
constexpr MacroInfo macro(std::uint16_t number, const char* name, const char* description,
                          const OutputInfo (&outputs)[NO]) {
  return {number, &thunk<Handler>, name, description, nullptr, 0, outputs, NO};
}

}  // namespace trueaxis::macros
