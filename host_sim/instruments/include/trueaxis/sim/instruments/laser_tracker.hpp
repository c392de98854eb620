// A virtual laser tracker (AT960 class): it reads points of a machine's frame
// M in its own frame, with its noise. It knows the machine only by where it
// stands in front of it (convention 2); tools/gantry_measure.hpp points it at
// the virtual gantry. Host only.
//
// Conventions
//  1. Tracker frame: origin at the tracker head, +Z up (levelled, away from
//     gravity), +X its zero azimuth. The CSV samples are written in this frame.
//  2. Placement (place_tracker): the machine frame M is not quite level: level
//     coordinates are level_R_machine = AngleAxis(tilt_x, X) AngleAxis(tilt_y, Y)
//     applied to M (the machine's foundation error). For a machine whose front
//     is the plane y = front_y_mm of M, centred at x = centre_x_mm, the tracker stands at
//         P = (centre_x_mm, front_y_mm - 1000 distance_m, height_mm)   (frame M),
//     i.e. distance_m metres in front of the machine's front, facing it, and
//     its frame is turned by yaw_deg about the vertical from level X:
//         level_R_tracker = AngleAxis(yaw, Z),  machine_R_tracker = level_R_machine^T level_R_tracker.
//  3. Noise. An AT960 states its point accuracy as an MPE of +-(15 um + 6 um/m)
//     and its distance meter (ADM) as +-10 um. Read as 2 sigma, and split along
//     the line of sight at range r (metres):
//         radial (distance):     sigma_r = 0.5 * 10 um                = 5 um,
//         transverse (angles):   sigma_t = 0.5 * (15 um + 6 um/m * r) = 7.5 um + 3 um/m * r
//     per direction, in each of the two directions across the line of sight
//     (horizontal: unit(Z x e_r); vertical: e_r x horizontal). So every
//     direction's 2 sigma is within the MPE, the transverse directions reach it,
//     and the transverse term (the angle encoders' error times the range) grows
//     with range: 13.5 um at 2 m, 25.5 um at 6 m; sigma_r stays 5 um. A
//     reading is p + sigma_r n1 e_r + sigma_t (n2 e_h + n3 e_v), n1..n3
//     independent standard normal deviates from SimRng (three per reading, in
//     that order); with noise off, p exactly and no draws. A point straight
//     above or below the tracker takes X as its horizontal direction.
#pragma once

#include "trueaxis/core/types.hpp"
#include "trueaxis/sim/sim_math.hpp"

namespace trueaxis::sim {

// Convention 3; MPEs in mm, read as 2 sigma.
struct TrackerSpec {
  double radial_mpe_mm = 0.010;
  double transverse_mpe_mm = 0.015;
  double transverse_mpe_per_m_mm = 0.006;
  double sigma_per_mpe = 0.5;
};

// Convention 2.
struct TrackerPlacement {
  double distance_m = 2.5;
  double height_mm = 600.0;
  double yaw_deg = 35.0;
  double machine_tilt_x_arcsec = 10.0;
  double machine_tilt_y_arcsec = -15.0;
};

class LaserTracker {
 public:
  LaserTracker(const RigidTransform& machine_T_tracker, const TrackerSpec& spec, bool noise);

  const RigidTransform& machine_T_tracker() const { return machine_T_tracker_; }
  const RigidTransform& tracker_T_machine() const { return tracker_T_machine_; }
  const TrackerSpec& spec() const { return spec_; }
  bool noise() const { return noise_; }

  core::Vec3 to_tracker(const core::Vec3& p_machine) const { return tracker_T_machine_.apply(p_machine); }

  // Convention 3, range in mm.
  double radial_sigma_mm(double range_mm) const;
  double transverse_sigma_mm(double range_mm) const;

  // The line-of-sight basis of a point in the tracker frame: columns e_r, e_h, e_v.
  static core::Mat3 sight_basis(const core::Vec3& p_tracker);

  // One reading of a point of frame M, in the tracker frame (convention 3).
  core::Vec3 measure(const core::Vec3& p_machine, SimRng& rng) const;

 private:
  RigidTransform machine_T_tracker_;
  RigidTransform tracker_T_machine_;
  TrackerSpec spec_;
  bool noise_;
};

// Convention 2, in front of a machine whose front is the plane y = front_y_mm
// of its frame, centred at x = centre_x_mm.
LaserTracker place_tracker(double centre_x_mm, double front_y_mm, const TrackerPlacement& placement,
                           const TrackerSpec& spec = TrackerSpec{}, bool noise = true);

}  // namespace trueaxis::sim
