// Little-endian encoding of stored values (the rigidity table's codec, the
// persistent records' headers and payloads), so a record written on one
// controller reads the same on another whatever its byte order.
#pragma once

#include <cstdint>
#include <cstring>
#include <limits>

namespace trueaxis::core {

static_assert(std::numeric_limits<double>::is_iec559 && sizeof(double) == 8, "binary64 doubles required");

inline void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}
inline std::uint16_t get_u16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }

inline void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
inline std::uint32_t get_u32(const std::uint8_t* p) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

inline void put_f64(std::uint8_t* p, double value) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  for (int i = 0; i < 8; ++i) p[i] = static_cast<std::uint8_t>(bits >> (8 * i));
}
inline double get_f64(const std::uint8_t* p) {
  std::uint64_t bits = 0;
  for (int i = 7; i >= 0; --i) bits = (bits << 8) | p[i];
  double value = 0.0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// Cursors over a record's reals, for codecs that list their fields once and run
// the list in both directions: `io(x)` puts or gets a double, or each
// coefficient of a fixed-size vector in index order.
struct F64Writer {
  std::uint8_t* p;
  void operator()(double v) {
    put_f64(p, v);
    p += 8;
  }
  template <typename V>
  void operator()(const V& v) {
    for (int i = 0; i < static_cast<int>(v.size()); ++i) (*this)(static_cast<double>(v(i)));
  }
};

struct F64Reader {
  const std::uint8_t* p;
  void operator()(double& v) {
    v = get_f64(p);
    p += 8;
  }
  template <typename V>
  void operator()(V& v) {
    for (int i = 0; i < static_cast<int>(v.size()); ++i) (*this)(v(i));
  }
};

}  // namespace trueaxis::core
