// A method's calibration table as the controller keeps it: the record it is
// stored in, the live copy the real-time task reads (live_table.hpp), and why
// there is none. One template for every method that stores a table.
//
// Contract
//  1. Spec names the table and its record:
//       using Type = ...;                      the decoded table
//       static constexpr RecordSpec kRecord;   key, layout version, capacity, name
//       static Status decode(const std::uint8_t*, std::size_t, Type&);
//       static std::size_t encode(const Type&, std::uint8_t*, std::size_t);
//       static std::size_t bytes(const Type&); its encoded length (<= capacity)
//     TableCodec below makes all but kRecord from a table type and its codec
//     in firmware_core.
//     Module::start() loads the record into the live table (load()), or marks
//     it damaged; a method stages a new table through its context
//     (MethodContext::stage_table), and the module makes it live after the
//     record's save succeeded (commit()), in the same step.
//  2. read_or(f): f(table) on the live table, or the reason there is none:
//     kNoTable (none stored), kTableDamaged (the record failed its CRC at
//     start), kTableInvalid (it did not decode). Const, lock-free, no
//     allocation: the controller's real-time task calls it.
//  3. The table staged must stay where it is until the commit (the method's
//     work in the work arena, or its state): the module commits in the step
//     after the macro's last one, and no other macro runs in between.
//  4. The home. A Spec with `static std::uint16_t home_of(const Type&)` (M3's
//     table: the home identity it was measured under) is applied only under
//     that home: use_or(f) is read_or(f) but kHomeChanged while the table's
//     home is not the machine's (#904, set_home(): the module at start and
//     after every write of #904). read_or stays open for reports and the
//     exact export. Without home_of, use_or is read_or. Lock-free: the home
//     is a relaxed 16-bit atomic.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/keyed_store.hpp"
#include "trueaxis/macros/live_table.hpp"

namespace trueaxis::macros {

// Contract 1's Spec but kRecord, from a table type T and its codec: Decode and
// Encode as firmware_core's decode_* and encode_*, Bytes the encoded length of
// every table (a std::size_t) or its function of the table. A method's record:
//   struct FramesRecord : TableCodec<core::GantryTable, &core::decode_gantry_table,
//                                    &core::encode_gantry_table, core::kGantryTableBytes> {
//     static constexpr RecordSpec kRecord{4, 1, 3072, "gantry_frames"};
//   };
template <typename T, core::Status (*Decode)(const std::uint8_t*, std::size_t, T&),
          std::size_t (*Encode)(const T&, std::uint8_t*, std::size_t), auto Bytes>
struct TableCodec {
  using Type = T;
  static core::Status decode(const std::uint8_t* bytes, std::size_t length, Type& out) {
    return Decode(bytes, length, out);
  }
  static std::size_t encode(const Type& t, std::uint8_t* out, std::size_t capacity) {
    return Encode(t, out, capacity);
  }
  static std::size_t bytes(const Type& t) {
    if constexpr (std::is_invocable_r_v<std::size_t, decltype(Bytes), const Type&>) {
      return Bytes(t);
    } else {
      static_cast<void>(t);
      return Bytes;
    }
  }
};

// Contract 4: whether Spec records a home.
template <typename Spec, typename = void>
struct RecordsHome : std::false_type {};
template <typename Spec>
struct RecordsHome<Spec, std::void_t<decltype(Spec::home_of(std::declval<const typename Spec::Type&>()))>>
    : std::true_type {};

template <typename Spec>
class StoredTable {
 public:
  using Type = typename Spec::Type;

  StoredTable() = default;
  StoredTable(const StoredTable&) = delete;
  StoredTable& operator=(const StoredTable&) = delete;

  // Contract 2.
  template <typename F>
  auto read_or(F f) const -> decltype(f(std::declval<const Type&>())) {
    return macros::read_or(live_, missing_, f);
  }

  // Contract 4: the table to apply, or why not (kHomeChanged besides contract 2's).
  template <typename F>
  auto use_or(F f) const -> decltype(f(std::declval<const Type&>())) {
    using R = decltype(f(std::declval<const Type&>()));
    if constexpr (RecordsHome<Spec>::value) {
      const std::uint16_t home = home_.load(std::memory_order_relaxed);
      return read_or([&](const Type& t) -> R {
        if (Spec::home_of(t) != home) return R(core::Status::kHomeChanged);
        return f(t);
      });
    } else {
      return read_or(f);
    }
  }

  // Contract 4: the machine's home now (Module).
  void set_home(std::uint16_t home) { home_.store(home, std::memory_order_relaxed); }
  std::uint16_t home() const { return home_.load(std::memory_order_relaxed); }

  // f(table) on the live table; false when there is none (live_table.hpp).
  template <typename F>
  bool read(F&& f) const {
    return live_.read(static_cast<F&&>(f));
  }

  bool has_table() const { return live_.has_table(); }
  core::Status missing() const { return missing_; }

  // Module::start(): a record of `length` bytes (0: none stored) decoded into
  // `scratch`, then made live; one that does not decode makes nothing live and
  // the queries say kTableInvalid.
  void load(const std::uint8_t* bytes, std::size_t length, Type& scratch) {
    load_stored(live_, scratch, missing_, bytes, length, Spec::decode);
  }

  // Module::start(): the record failed its CRC; the queries say kTableDamaged.
  void damaged() { missing_ = core::Status::kTableDamaged; }

  // The table a macro staged (contract 3), made live by commit().
  void stage(const Type& table) { staged_ = &table; }
  void commit() {
    if (staged_ != nullptr) live_.publish(*staged_);
    staged_ = nullptr;
  }

 private:
  LiveTable<Type> live_;
  core::Status missing_ = core::Status::kNoTable;
  const Type* staged_ = nullptr;
  std::atomic<std::uint16_t> home_{0};
  static_assert(std::atomic<std::uint16_t>::is_always_lock_free, "the real-time task reads the home");
};

}  // namespace trueaxis::macros
