#include "trueaxis/core/leveling.hpp"
#include "trueaxis/macros/macro_table.hpp"

namespace trueaxis::macros {

namespace {

core::LevelConfig read_config(const MacroContext& ctx) {
  core::LevelConfig c;
  c.a_min_deg = ctx.in(var::kAMin);
  c.a_max_deg = ctx.in(var::kAMax);
  c.c_min_deg = ctx.in(var::kCMin);
  c.c_max_deg = ctx.in(var::kCMax);
  c.a_sign = ctx.in(var::kASign);
  c.c_sign = ctx.in(var::kCSign);
  c.probe_sigma_mm = ctx.in(var::kProbeSigma);
  c.max_direction_sigma_deg = ctx.in(var::kMaxDirectionSigma);
  return c;
}

core::Vec3 read_point(const MacroContext& ctx, std::uint16_t x_number) {
  return core::Vec3(ctx.in(x_number), ctx.in(static_cast<std::uint16_t>(x_number + 1)),
                    ctx.in(static_cast<std::uint16_t>(x_number + 2)));
}

// Shared by 9810 and 9811: everything but where the points come from.
core::Status level_and_report(MacroContext& ctx, const core::Vec3* points, std::size_t count) {
  core::LevelInput input;
  input.points_mm = points;
  input.count = count;
  input.probe_pose = {ctx.in(var::kArgA), ctx.in(var::kArgC)};
  input.current_pose = input.probe_pose;  // the table has not moved since probing
  input.outward_hint_machine = read_point(ctx, var::kArgI);

  const core::Result<core::LevelResult> r = core::level_face(input, read_config(ctx));
  if (!r.ok()) return r.status();
  const core::LevelResult& out = r.value();
  ctx.out(var::kLevelC, out.chosen.c_deg);
  ctx.out(var::kLevelA, out.chosen.a_deg);
  ctx.out(var::kLevelOtherC, out.other.c_deg);
  ctx.out(var::kLevelOtherA, out.other.a_deg);
  ctx.out(var::kLevelNormalX, out.normal_table.x());
  ctx.out(var::kLevelNormalY, out.normal_table.y());
  ctx.out(var::kLevelNormalZ, out.normal_table.z());
  ctx.out(var::kLevelTilt, out.tilt_deg);
  ctx.out(var::kLevelTiltSigma, out.tilt_sigma_arcsec);
  ctx.out(var::kLevelCSigma, out.c_sigma_arcsec);
  ctx.out(var::kLevelDirectionSigma, out.direction_sigma_arcsec);
  ctx.out(var::kLevelFlatness, out.flatness_mm);
  ctx.out(var::kLevelPointCount, static_cast<double>(out.count));
  ctx.out(var::kLevelOutlierPoint, static_cast<double>(out.outlier_point));
  ctx.out(var::kLevelMaxResidual, out.max_standardized_residual);
  ctx.out(var::kLevelOtherReachable, out.other.reachable ? 1.0 : 0.0);
  return core::Status::kOk;
}

}  // namespace

core::Status run_level_3pt(MacroContext& ctx) {
  const core::Vec3 points[3] = {read_point(ctx, var::kG57), read_point(ctx, var::kG58), read_point(ctx, var::kG59)};
  return level_and_report(ctx, points, 3);
}

core::Status run_level_points(MacroContext& ctx) {
  const double q = ctx.in(var::kArgQ);
  if (!(q >= 3.0 && q <= static_cast<double>(core::kMaxPlanePoints)) || q != std::floor(q)) {
    return core::Status::kArgumentOutOfRange;
  }
  const std::size_t count = static_cast<std::size_t>(q);
  core::Vec3 points[core::kMaxPlanePoints];
  for (std::size_t k = 0; k < count; ++k) {
    points[k] = read_point(ctx, static_cast<std::uint16_t>(var::kPointList + 3 * k));
  }
  return level_and_report(ctx, points, count);
}

}  // namespace trueaxis::macros
