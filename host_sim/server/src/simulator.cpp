#include "trueaxis/sim/server/simulator.hpp"

#include <cmath>
#include <utility>

#include "trueaxis/sim/instruments/calibration_ball.hpp"
#include "trueaxis/sim/instruments/touch_probe.hpp"

namespace trueaxis::sim {

using macros::AccessFault;

bool is_probe_target(double target) {
  for (std::uint16_t g = macros::var::kG54; g <= macros::var::kG59; g = static_cast<std::uint16_t>(g + 20)) {
    if (target == g) return true;
  }
  for (std::uint16_t k = 0; k < core::kMaxPlanePoints; ++k) {
    if (target == macros::var::kPointList + 3 * k) return true;
  }
  return false;
}

Simulator::Simulator(macros::Module& module, const FaceConfig& face, std::uint64_t seed, bool errors_on,
                     const CradleErrors& errors, const CradlePivot& pivot)
    : module_(module), face_(face), errors_(errors), pivot_(pivot), ideal_(face, CradleErrors{}, pivot),
      with_errors_(face, errors, pivot),
      spindle_(realistic_spindle()) {
  for (const macros::VarInfo& v : kSimMap) state_.values[v.number - simvar::kFirst] = v.default_value;
  state_.values[simvar::kErrors - simvar::kFirst] = errors_on ? 1.0 : 0.0;
  state_.rng = SimRng(seed);
}

CradleMachine Simulator::drifted(const double* values) const {
  CradleErrors e = errors_;
  e.local_a_deg = values[simvar::kDriftA - simvar::kFirst];
  e.local_arcsec = values[simvar::kDriftArcsec - simvar::kFirst];
  return CradleMachine(face_, e, pivot_);
}

const CradleMachine& Simulator::machine_for(const double* values) const {
  return values[simvar::kErrors - simvar::kFirst] == 1.0 ? with_errors_ : ideal_;
}

void Simulator::after_request() {
  if (state_.values[simvar::kHold - simvar::kFirst] != 1.0) module_.step();
}

double Simulator::value(std::uint16_t number) const {
  return find_sim_var(number) != nullptr ? read_one(number) : 0.0;
}

double Simulator::read_one(std::uint16_t number) const {
  const double* v = state_.values;
  const double a = v[simvar::kAxisA - simvar::kFirst];
  const double c = v[simvar::kAxisC - simvar::kFirst];
  const double ball_z = v[simvar::kBallZ - simvar::kFirst];
  const CradleMachine& m = machine_for(v);
  switch (number) {
    case simvar::kTrueNormalX: return m.normal_table().x();
    case simvar::kTrueNormalY: return m.normal_table().y();
    case simvar::kTrueNormalZ: return m.normal_table().z();
    case simvar::kTrueTilt: return m.tilt_deg_at(a, c);
    case simvar::kTrueRotvecX:
    case simvar::kTrueRotvecY:
    case simvar::kTrueRotvecZ:
      return m.rotation_vector_rad(a, ball_z)[number - simvar::kTrueRotvecX] * kArcsecPerRad;
    case simvar::kTrueAPositioningError: return m.a_positioning_error_arcsec(a, ball_z);
    case simvar::kTrueADriveError: return m.a_drive_error_arcsec(a);
    case simvar::kTrueCToAOffset: return m.c_to_a_offset_mm();
    case simvar::kTrueCToASquareness: return m.c_to_a_squareness_arcsec();
    case simvar::kTrueAPointX:
    case simvar::kTrueAPointY:
    case simvar::kTrueAPointZ: return m.a_axis().point_mm[number - simvar::kTrueAPointX];
    case simvar::kTrueADirX:
    case simvar::kTrueADirY:
    case simvar::kTrueADirZ: return m.a_axis().direction[number - simvar::kTrueADirX];
    case simvar::kTrueCCentreX:
    case simvar::kTrueCCentreY:
    case simvar::kTrueCCentreZ: return m.c_centre_at(a, ball_z)[number - simvar::kTrueCCentreX];
    case simvar::kTrueCDirX:
    case simvar::kTrueCDirY:
    case simvar::kTrueCDirZ: return m.c_axis_at(a).direction[number - simvar::kTrueCDirX];
    case simvar::kFaceNormalX:
    case simvar::kFaceNormalY:
    case simvar::kFaceNormalZ: return m.face_at(a, c).normal[number - simvar::kFaceNormalX];
    case simvar::kFaceOffset: {
      const Plane face = m.face_at(a, c);
      return face.normal.dot(face.point_mm);
    }
    case simvar::kBallMachineX:
    case simvar::kBallMachineY:
    case simvar::kBallMachineZ: {
      const core::Vec3 ball(v[simvar::kBallX - simvar::kFirst], v[simvar::kBallY - simvar::kFirst], ball_z);
      return m.machine_T_table(a, c).apply(ball)[number - simvar::kBallMachineX];
    }
    case simvar::kTipErrorX:
    case simvar::kTipErrorY:
    case simvar::kTipErrorZ: {
      if (v[simvar::kSpindle - simvar::kFirst] != 1.0) return 0.0;
      return spindle_.tool_tip_error_mm(v[simvar::kToolLength - simvar::kFirst],
                                        v[simvar::kSpindleAngle - simvar::kFirst])[number - simvar::kTipErrorX];
    }
    default: return v[number - simvar::kFirst];
  }
}

AccessFault Simulator::do_read(std::uint16_t first, std::uint16_t count, double* out, macros::ClientId) {
  for (std::uint32_t n = first; n < static_cast<std::uint32_t>(first) + count; ++n) {
    if (find_sim_var(static_cast<std::uint16_t>(n)) == nullptr) return AccessFault::kUndefined;
  }
  for (std::uint16_t i = 0; i < count; ++i) out[i] = read_one(static_cast<std::uint16_t>(first + i));
  return AccessFault::kNone;
}

AccessFault Simulator::do_write(std::uint16_t first, std::uint16_t count, const double* values,
                                macros::ClientId client) {
  for (std::uint32_t n = first; n < static_cast<std::uint32_t>(first) + count; ++n) {
    if (find_sim_var(static_cast<std::uint16_t>(n)) == nullptr) return AccessFault::kUndefined;
  }
  for (std::uint16_t i = 0; i < count; ++i) {
    const macros::VarInfo* info = find_sim_var(static_cast<std::uint16_t>(first + i));
    if (info == nullptr) return AccessFault::kUndefined;
    if (info->access == macros::Access::kReadOnly) return AccessFault::kReadOnly;
  }
  for (std::uint16_t i = 0; i < count; ++i) {
    const macros::VarInfo* info = find_sim_var(static_cast<std::uint16_t>(first + i));
    const AccessFault f = info == nullptr ? AccessFault::kUndefined : macros::check_value(*info, values[i]);
    if (f != AccessFault::kNone) return f;
  }
  State next = state_;
  bool probe_requested = false;
  bool measure_requested = false;
  for (std::uint16_t i = 0; i < count; ++i) {
    const auto number = static_cast<std::uint16_t>(first + i);
    next.values[number - simvar::kFirst] = values[i];
    if (number == simvar::kProbeInto) probe_requested = true;
    if (number == simvar::kBallMeasure && values[i] == 1.0) measure_requested = true;
  }
  const auto drift_of = [](const State& st) {
    return std::make_pair(st.values[simvar::kDriftA - simvar::kFirst], st.values[simvar::kDriftArcsec - simvar::kFirst]);
  };
  const bool drift_changed = drift_of(next) != drift_of(state_);
  if (drift_changed) with_errors_ = drifted(next.values);
  if (probe_requested) {
    const double target = next.values[simvar::kProbeInto - simvar::kFirst];
    const AccessFault f =
        is_probe_target(target) ? probe(next, static_cast<std::uint16_t>(target), client) : AccessFault::kOutOfRange;
    if (f != AccessFault::kNone) {
      if (drift_changed) with_errors_ = drifted(state_.values);  // contract 3: nothing changes
      return f;
    }
  }
  if (measure_requested) measure_ball(next);
  state_ = next;
  return AccessFault::kNone;
}

void Simulator::measure_ball(State& next) const {
  double* v = next.values;
  CalibrationBall ball;
  ball.centre_table_mm = core::Vec3(v[simvar::kBallX - simvar::kFirst], v[simvar::kBallY - simvar::kFirst],
                                    v[simvar::kBallZ - simvar::kFirst]);
  ball.sigma_mm = v[simvar::kBallSigma - simvar::kFirst];
  const RigidTransform machine_T_table =
      machine_for(v).machine_T_table(v[simvar::kAxisA - simvar::kFirst], v[simvar::kAxisC - simvar::kFirst]);
  const core::Vec3 p = ball.measure(machine_T_table, next.rng);
  v[simvar::kLastBallX - simvar::kFirst] = p.x();
  v[simvar::kLastBallY - simvar::kFirst] = p.y();
  v[simvar::kLastBallZ - simvar::kFirst] = p.z();
}

AccessFault Simulator::probe(State& next, std::uint16_t target, macros::ClientId client) {
  const double* v = next.values;
  const Plane face = machine_for(v).face_at(v[simvar::kAxisA - simvar::kFirst], v[simvar::kAxisC - simvar::kFirst]);
  core::Vec3 touch_machine;
  if (!TouchProbe::touch(face, v[simvar::kProbeX - simvar::kFirst], v[simvar::kProbeY - simvar::kFirst],
                         touch_machine)) {
    return AccessFault::kOutOfRange;
  }
  const TouchProbe probe{v[simvar::kProbeSigma - simvar::kFirst]};
  const core::Vec3 p = probe.read(touch_machine, next.rng);
  const double point[3] = {p.x(), p.y(), p.z()};
  // The module's own write path, for the client that asked for the probe: its
  // validation, busy check, persistence and the macro interface's grant apply.
  const AccessFault f = module_.write(target, 3, point, client);
  if (f != AccessFault::kNone) return f;
  next.values[simvar::kLastProbeX - simvar::kFirst] = point[0];
  next.values[simvar::kLastProbeY - simvar::kFirst] = point[1];
  next.values[simvar::kLastProbeZ - simvar::kFirst] = point[2];
  return AccessFault::kNone;
}

}  // namespace trueaxis::sim
