#include "trueaxis/sim/instruments/laser_tracker.hpp"

namespace trueaxis::sim {

using core::Mat3;
using core::Vec3;

LaserTracker::LaserTracker(const RigidTransform& machine_T_tracker, const TrackerSpec& spec, bool noise)
    : machine_T_tracker_(machine_T_tracker),
      tracker_T_machine_(machine_T_tracker.inverse()),
      spec_(spec),
      noise_(noise) {}

double LaserTracker::radial_sigma_mm(double /*range_mm*/) const { return spec_.sigma_per_mpe * spec_.radial_mpe_mm; }

double LaserTracker::transverse_sigma_mm(double range_mm) const {
  return spec_.sigma_per_mpe * (spec_.transverse_mpe_mm + spec_.transverse_mpe_per_m_mm * range_mm / 1000.0);
}

core::Mat3 LaserTracker::sight_basis(const core::Vec3& p_tracker) {
  const Vec3 e_r = p_tracker.normalized();
  Vec3 e_h = Vec3::UnitZ().cross(e_r);
  // Straight up or down: any horizontal direction will do; X, as documented.
  e_h = e_h.norm() > 1e-12 ? Vec3(e_h.normalized()) : Vec3(Vec3::UnitX());
  Mat3 basis;
  basis << e_r, e_h, e_r.cross(e_h);
  return basis;
}

core::Vec3 LaserTracker::measure(const core::Vec3& p_machine, SimRng& rng) const {
  const Vec3 p = to_tracker(p_machine);
  if (!noise_) return p;
  const double range = p.norm();
  const Mat3 basis = sight_basis(p);
  const double n1 = rng.normal();
  const double n2 = rng.normal();
  const double n3 = rng.normal();
  return p + radial_sigma_mm(range) * n1 * basis.col(0) +
         transverse_sigma_mm(range) * (n2 * basis.col(1) + n3 * basis.col(2));
}

LaserTracker place_tracker(double centre_x_mm, double front_y_mm, const TrackerPlacement& placement,
                           const TrackerSpec& spec, bool noise) {
  const Mat3 level_R_machine = turn(Vec3::UnitX(), placement.machine_tilt_x_arcsec / kArcsecPerRad) *
                               turn(Vec3::UnitY(), placement.machine_tilt_y_arcsec / kArcsecPerRad);
  const Mat3 level_R_tracker = turn(Vec3::UnitZ(), core::deg_to_rad(placement.yaw_deg));
  RigidTransform machine_T_tracker;
  machine_T_tracker.rotation = level_R_machine.transpose() * level_R_tracker;
  machine_T_tracker.translation_mm =
      Vec3(centre_x_mm, front_y_mm - 1000.0 * placement.distance_m, placement.height_mm);
  return LaserTracker(machine_T_tracker, spec, noise);
}

}  // namespace trueaxis::sim
