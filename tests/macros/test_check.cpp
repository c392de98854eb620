// check.hpp on its own: a figure's verdict at the exact boundaries of
// convention 2, NaN, and publish_check's outputs (convention 3) through a
// stand-in for a method's context: the worst figure is the worst verdict's,
// then the largest ratio; Q out of range and no figure are refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "trueaxis/macros/check.hpp"

namespace {

namespace m = trueaxis::macros;
namespace v = trueaxis::macros::var;
using trueaxis::core::Status;

m::CheckFigure figure(double deviation, double sigma, double tolerance) {
  m::CheckFigure f;
  f.deviation = deviation;
  f.sigma = sigma;
  f.tolerance = tolerance;
  return f;
}

// What publish_check needs of a MethodContext: in<Q>(), out<N>() and log().
struct FakeContext {
  double q = 0.0;
  double results[100] = {};
  m::LogEntry logged;
  int logs = 0;
  void log(const m::LogEntry& e) {
    logged = e;
    ++logs;
  }
  template <std::uint16_t N>
  double in() const {
    static_assert(N == v::kArgQ, "publish_check reads only Q");
    return q;
  }
  template <std::uint16_t N>
  void out(double value) {
    results[N - 100] = value;
  }
};

}  // namespace

TEST_CASE("a figure's verdict at the exact boundaries: fail beyond the tolerance, warn within it by less than 2 sigma",
          "[check]") {
  const double t = 10.0;
  CHECK(m::judge(figure(6.0, 2.0, t)) == m::Verdict::kPass);                      // |d| + 2 sigma == T
  CHECK(m::judge(figure(6.0 + std::ldexp(1.0, -48), 2.0, t)) == m::Verdict::kWarn);  // 2 ulp of T over, exactly
  CHECK(m::judge(figure(-6.0, 2.0, t)) == m::Verdict::kPass);                     // the sign does not matter
  CHECK(m::judge(figure(10.0, 0.0, t)) == m::Verdict::kPass);                     // |d| == T, no uncertainty
  CHECK(m::judge(figure(10.0, 1e-9, t)) == m::Verdict::kWarn);                    // |d| == T is not beyond it
  CHECK(m::judge(figure(std::nextafter(10.0, 11.0), 0.0, t)) == m::Verdict::kFail);
  CHECK(m::judge(figure(-10.5, 0.0, t)) == m::Verdict::kFail);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(m::judge(figure(nan, 0.0, t)) == m::Verdict::kFail);
  CHECK(m::judge(figure(0.0, nan, t)) == m::Verdict::kFail);
  CHECK(m::check_ratio(figure(nan, 0.0, t)) == HUGE_VAL);
  CHECK(m::check_ratio(figure(6.0, 2.0, t)) == 1.0);
}

TEST_CASE("publish_check: the worst figure is the worst verdict's, then the largest ratio; Q picks a figure",
          "[check]") {
  // A warn with a large ratio, a fail with a smaller one, a pass.
  const std::vector<m::CheckFigure> figures = {figure(5.0, 4.0, 10.0), figure(10.5, 0.01, 10.0),
                                               figure(1.0, 0.1, 10.0)};
  const auto at = [&](std::size_t k) {
    m::CheckFigure f = figures[k];
    f.kind = static_cast<std::uint16_t>(k + 1);
    f.item = static_cast<std::uint16_t>(10 + k);
    return f;
  };
  FakeContext ctx;
  REQUIRE(m::publish_check(ctx, figures.size(), at).status == Status::kOk);
  CHECK(ctx.results[0] == 2.0);  // fail
  CHECK(ctx.results[1] == 3.0);
  CHECK(ctx.results[2] == 2.0);  // the fail, though the warn's ratio (1.3) is larger than its (1.052)
  CHECK(ctx.results[3] == Approx(1.052));
  CHECK(ctx.results[4] == 2.0);  // Q = 0: the worst figure's verdict, kind, item, values
  CHECK(ctx.results[5] == 2.0);
  CHECK(ctx.results[6] == 11.0);
  CHECK(ctx.results[9] == 10.5);
  CHECK(ctx.results[10] == 0.01);
  CHECK(ctx.results[11] == 10.0);
  ctx.q = 1.0;
  REQUIRE(m::publish_check(ctx, figures.size(), at).status == Status::kOk);
  CHECK(ctx.results[4] == 1.0);  // figure 1: warn
  CHECK(ctx.results[6] == 10.0);
  CHECK(ctx.results[2] == 2.0);  // the summary is the same whichever figure Q picks
  ctx.q = 4.0;
  CHECK(m::publish_check(ctx, figures.size(), at).status == Status::kArgumentOutOfRange);
  ctx.q = 0.5;
  CHECK(m::publish_check(ctx, figures.size(), at).status == Status::kArgumentOutOfRange);
  ctx.q = 0.0;
  CHECK(m::publish_check(ctx, 0, at).status == Status::kNothingToCheck);

  // Among equal verdicts the largest ratio; a NaN counts as the largest.
  const std::vector<m::CheckFigure> passes = {figure(1.0, 0.1, 10.0), figure(3.0, 0.1, 10.0),
                                              figure(std::numeric_limits<double>::quiet_NaN(), 0.1, 10.0)};
  FakeContext c2;
  REQUIRE(m::publish_check(c2, 2, [&](std::size_t k) { return passes[k]; }).status == Status::kOk);
  CHECK(c2.results[0] == 0.0);
  CHECK(c2.results[2] == 2.0);
  REQUIRE(m::publish_check(c2, 3, [&](std::size_t k) { return passes[k]; }).status == Status::kOk);
  CHECK(c2.results[0] == 2.0);
  CHECK(c2.results[2] == 3.0);
}

TEST_CASE("publish_check logs with Q = 0 only: the verdict and, per kind, the worst figure of that kind",
          "[check][log]") {
  // Kind 1: a warn of ratio 1.3, a fail of ratio 1.052, a pass: the fail is
  // logged. Kind 2: two passes, the larger ratio logged. Kind 7 (beyond the
  // log's six kinds) decides the verdict and is not logged.
  const std::vector<m::CheckFigure> figures = {figure(5.0, 4.0, 10.0), figure(10.5, 0.01, 10.0), figure(-3.0, 1.0, 10.0),
                                               figure(1.0, 0.2, 10.0), figure(2.0, 0.1, 20.0), figure(50.0, 0.0, 1.0)};
  const std::uint16_t kinds[] = {1, 1, 2, 1, 2, 7};
  const auto at = [&](std::size_t k) {
    m::CheckFigure f = figures[k];
    f.kind = kinds[k];
    f.item = static_cast<std::uint16_t>(k + 1);
    return f;
  };
  FakeContext ctx;
  REQUIRE(m::publish_check(ctx, figures.size(), at).status == Status::kOk);
  REQUIRE(ctx.logs == 1);
  const m::LogEntry& e = ctx.logged;
  CHECK(e.type == m::LogType::kCheck);
  CHECK(e.verdict == 2);
  REQUIRE(e.figure_count == 2);
  CHECK(e.figures[0].kind == 1);
  CHECK(e.figures[0].item == 2);  // the fail, not the warn of larger ratio
  CHECK(e.figures[0].value == 10.5F);
  CHECK(e.figures[0].sigma == 0.01F);
  CHECK(e.figures[0].tolerance == 10.0F);
  CHECK(e.figures[1].kind == 2);
  CHECK(e.figures[1].item == 3);  // ratio (3 + 2) / 10 = 0.5 over (2 + 0.2) / 20 = 0.11
  CHECK(e.figures[1].value == -3.0F);
  ctx.q = 1.0;
  REQUIRE(m::publish_check(ctx, figures.size(), at).status == Status::kOk);
  CHECK(ctx.logs == 1);  // a figure's query logs nothing
}

TEST_CASE("publish_check on a tie: the first of equal verdicts and ratios is the worst, and is logged for its kind",
          "[check][log]") {
  // Figures 1 and 2 of kind 1 both warn at ratio (6 + 2 x 2.5) / 10, exactly
  // the same; figure 3 (kind 2) fails; figures 4, 5 (kind 3) tie as passes.
  // Then one figure of the tie a few ulps of ratio above the other: it wins.
  const double above = 6.0 + std::ldexp(1.0, -47);  // |d| + 2 sigma = 11 + 2^-47, exactly
  std::vector<m::CheckFigure> figures = {figure(6.0, 2.5, 10.0), figure(-6.0, 2.5, 10.0), figure(10.5, 0.0, 10.0),
                                         figure(1.0, 0.5, 10.0), figure(-1.0, 0.5, 10.0)};
  const std::uint16_t kinds[] = {1, 1, 2, 3, 3};
  const auto at = [&](std::size_t k) {
    m::CheckFigure f = figures[k];
    f.kind = kinds[k];
    f.item = static_cast<std::uint16_t>(k + 1);
    return f;
  };
  REQUIRE(m::check_ratio(figures[0]) == m::check_ratio(figures[1]));
  REQUIRE(m::judge(figures[0]) == m::judge(figures[1]));
  FakeContext ctx;
  REQUIRE(m::publish_check(ctx, figures.size(), at).status == Status::kOk);
  CHECK(ctx.results[2] == 3.0);  // the fail
  REQUIRE(ctx.logged.figure_count == 3);
  CHECK(ctx.logged.figures[0].item == 1);  // kind 1: the first of the tie
  CHECK(ctx.logged.figures[0].value == 6.0F);
  CHECK(ctx.logged.figures[2].item == 4);  // kind 3: the first of the tie
  // Without the fail, the warns tie for the check's worst: the first.
  figures[2] = figure(0.5, 0.0, 10.0);
  REQUIRE(m::publish_check(ctx, figures.size(), at).status == Status::kOk);
  CHECK(ctx.results[0] == 1.0);
  CHECK(ctx.results[2] == 1.0);
  CHECK(ctx.results[3] == m::check_ratio(figures[0]));
  CHECK(ctx.logged.figures[0].item == 1);
  // Figure 2's ratio just above figure 1's: now it is the worst, and its kind's.
  figures[1] = figure(-above, 2.5, 10.0);
  REQUIRE(m::check_ratio(figures[1]) > m::check_ratio(figures[0]));
  REQUIRE(m::publish_check(ctx, figures.size(), at).status == Status::kOk);
  CHECK(ctx.results[2] == 2.0);
  CHECK(ctx.logged.figures[0].item == 2);
  // Figure 1's just above figure 2's instead: figure 1 again.
  figures[1] = figure(-6.0, 2.5, 10.0);
  figures[0] = figure(above, 2.5, 10.0);
  REQUIRE(m::check_ratio(figures[0]) > m::check_ratio(figures[1]));
  REQUIRE(m::publish_check(ctx, figures.size(), at).status == Status::kOk);
  CHECK(ctx.results[2] == 1.0);
  CHECK(ctx.logged.figures[0].item == 1);
}
