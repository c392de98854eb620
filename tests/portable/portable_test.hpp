// A test framework small enough for the Cortex-M7 target: the same test sources
// run on the host (tests/portable) and under QEMU (tests/target).
//
// Contract
//  1. No heap, no exceptions, no RTTI, no stdio: output goes through a Sink, a
//     plain function that writes one NUL-terminated string (fwrite on the host,
//     semihosting on the target).
//  2. TA_TEST("sentence") { ... } defines a test case. Cases register themselves
//     at static initialisation into an intrusive list (each case is its own
//     node; nothing is allocated), in the order of their definitions within a
//     file; the order between files is the linker's.
//  3. TA_CHECK(cond), TA_CHECK_EQ(a, b), TA_CHECK_NEAR(a, b, tol) record a failure
//     with file:line and the expression, and the case goes on. TA_REQUIRE(cond)
//     also returns from the case. Each check returns whether it passed.
//     TA_CASE_INDEX(i) names the fixture a property loop is on; it is printed with
//     every failure until the next case starts.
//  4. run_all() runs every case and writes a line per case ("ok" or "FAIL"), at
//     most kMaxReportedFailures failures per case, and finally exactly
//     "N passed, M failed" (N, M: test cases). It returns M.
//  5. Numbers in failure messages are printed without printf: integers exactly,
//     doubles with 17 significant digits, the last of which may be off by one.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace trueaxis::test {

using Sink = void (*)(const char* text);

inline constexpr int kMaxReportedFailures = 8;

// A line of output built in a fixed buffer; text that does not fit is cut.
class Line {
 public:
  Line& text(const char* s) {
    while (*s != '\0' && length_ + 1 < sizeof(buffer_)) buffer_[length_++] = *s++;
    buffer_[length_] = '\0';
    return *this;
  }

  Line& uint(std::uint64_t value) {
    char digits[21];
    std::size_t i = sizeof(digits) - 1;
    digits[i] = '\0';
    do {
      digits[--i] = static_cast<char>('0' + static_cast<int>(value % 10));
      value /= 10;
    } while (value != 0);
    return text(&digits[i]);
  }

  Line& integer(std::int64_t value) {
    if (value < 0) {
      text("-");
      return uint(static_cast<std::uint64_t>(-(value + 1)) + 1);
    }
    return uint(static_cast<std::uint64_t>(value));
  }

  Line& real(double value) {
    if (std::isnan(value)) return text("nan");
    if (std::signbit(value)) {
      text("-");
      value = -value;
    }
    if (std::isinf(value)) return text("inf");
    if (value == 0.0) return text("0");
    int exponent = static_cast<int>(std::floor(std::log10(value)));
    double mantissa = value / std::pow(10.0, exponent);
    if (mantissa >= 10.0) {
      mantissa /= 10.0;
      ++exponent;
    } else if (mantissa < 1.0) {
      mantissa *= 10.0;
      --exponent;
    }
    char digits[20];
    std::size_t n = 0;
    for (int i = 0; i < 17; ++i) {
      const int d = static_cast<int>(mantissa);
      digits[n++] = static_cast<char>('0' + (d < 0 ? 0 : (d > 9 ? 9 : d)));
      if (i == 0) digits[n++] = '.';
      mantissa = (mantissa - d) * 10.0;
    }
    digits[n] = '\0';
    text(digits).text("e");
    return integer(exponent);
  }

  const char* c_str() const { return buffer_; }

 private:
  char buffer_[320] = {};
  std::size_t length_ = 0;
};

class TestCase {
 public:
  using Body = void (*)();

  TestCase(const char* name, const char* file, int line, Body body)
      : name_(name), file_(file), line_(line), body_(body) {
    if (tail_ == nullptr) {
      head_ = this;
    } else {
      tail_->next_ = this;
    }
    tail_ = this;
  }
  TestCase(const TestCase&) = delete;
  TestCase& operator=(const TestCase&) = delete;

  static int run_all(Sink sink);

  // Records a failure of the running case; called by the check functions.
  static void fail(const char* file, int line, const Line& what);

  static void set_case_index(std::int64_t index) { case_index_ = index; }

 private:
  const char* name_;
  const char* file_;
  int line_;
  Body body_;
  TestCase* next_ = nullptr;

  inline static TestCase* head_ = nullptr;
  inline static TestCase* tail_ = nullptr;
  inline static Sink sink_ = nullptr;
  inline static int failures_ = 0;  // of the running case
  inline static std::int64_t case_index_ = -1;
};

inline void TestCase::fail(const char* file, int line, const Line& what) {
  ++failures_;
  if (failures_ > kMaxReportedFailures || sink_ == nullptr) return;
  Line out;
  out.text("  ").text(file).text(":").integer(line).text(": ");
  if (case_index_ >= 0) out.text("[case ").integer(case_index_).text("] ");
  out.text(what.c_str()).text("\n");
  sink_(out.c_str());
}

inline int TestCase::run_all(Sink sink) {
  sink_ = sink;
  int passed = 0;
  int failed = 0;
  for (TestCase* t = head_; t != nullptr; t = t->next_) {
    failures_ = 0;
    case_index_ = -1;
    t->body_();
    Line out;
    if (failures_ == 0) {
      ++passed;
      out.text("ok   ").text(t->name_).text("\n");
      sink(out.c_str());
    } else {
      ++failed;
      if (failures_ > kMaxReportedFailures) {
        Line more;
        more.text("  ... ").integer(failures_ - kMaxReportedFailures).text(" more failures\n");
        sink(more.c_str());
      }
      out.text("FAIL ").text(t->name_).text(" (").text(t->file_).text(":").integer(t->line_).text(")\n");
      sink(out.c_str());
    }
  }
  Line summary;
  summary.integer(passed).text(" passed, ").integer(failed).text(" failed\n");
  sink(summary.c_str());
  return failed;
}

namespace detail {

template <typename T>
void append_value(Line& line, const T& value) {
  if constexpr (std::is_enum_v<T>) {
    append_value(line, static_cast<std::underlying_type_t<T>>(value));
  } else if constexpr (std::is_same_v<T, bool>) {
    line.text(value ? "true" : "false");
  } else if constexpr (std::is_floating_point_v<T>) {
    line.real(static_cast<double>(value));
  } else if constexpr (std::is_signed_v<T>) {
    line.integer(static_cast<std::int64_t>(value));
  } else {
    line.uint(static_cast<std::uint64_t>(value));
  }
}

inline bool check(bool ok, const char* expression, const char* file, int line) {
  if (!ok) {
    Line what;
    what.text("CHECK(").text(expression).text(") failed");
    TestCase::fail(file, line, what);
  }
  return ok;
}

template <typename A, typename B>
bool check_eq(const A& actual, const B& expected, const char* actual_text, const char* expected_text,
              const char* file, int line) {
  const bool ok = actual == expected;
  if (!ok) {
    Line what;
    what.text("CHECK_EQ(").text(actual_text).text(", ").text(expected_text).text(") failed: ");
    append_value(what, actual);
    what.text(" != ");
    append_value(what, expected);
    TestCase::fail(file, line, what);
  }
  return ok;
}

inline bool check_near(double actual, double expected, double tolerance, const char* actual_text,
                       const char* expected_text, const char* file, int line) {
  const double error = std::fabs(actual - expected);
  const bool ok = error <= tolerance;  // false for NaN
  if (!ok) {
    Line what;
    what.text("CHECK_NEAR(").text(actual_text).text(", ").text(expected_text).text(") failed: ");
    what.real(actual).text(" vs ").real(expected).text(", error ").real(error).text(" > ").real(tolerance);
    TestCase::fail(file, line, what);
  }
  return ok;
}

}  // namespace detail
}  // namespace trueaxis::test

#define TA_TEST_CAT2(a, b) a##b
#define TA_TEST_CAT(a, b) TA_TEST_CAT2(a, b)

#define TA_TEST(name)                                                                          \
  static void TA_TEST_CAT(ta_test_body_, __LINE__)();                                          \
  static ::trueaxis::test::TestCase TA_TEST_CAT(ta_test_case_, __LINE__){                      \
      name, __FILE__, __LINE__, &TA_TEST_CAT(ta_test_body_, __LINE__)};                        \
  static void TA_TEST_CAT(ta_test_body_, __LINE__)()

#define TA_CHECK(cond) ::trueaxis::test::detail::check(static_cast<bool>(cond), #cond, __FILE__, __LINE__)

#define TA_REQUIRE(cond)       \
  do {                         \
    if (!TA_CHECK(cond)) return; \
  } while (false)

#define TA_CHECK_EQ(actual, expected) \
  ::trueaxis::test::detail::check_eq((actual), (expected), #actual, #expected, __FILE__, __LINE__)

#define TA_CHECK_NEAR(actual, expected, tolerance)                                                  \
  ::trueaxis::test::detail::check_near((actual), (expected), (tolerance), #actual, #expected, __FILE__, \
                                       __LINE__)

#define TA_CASE_INDEX(index) ::trueaxis::test::TestCase::set_case_index(static_cast<std::int64_t>(index))
