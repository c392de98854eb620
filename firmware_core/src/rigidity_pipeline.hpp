// Internal to firmware_core: conventions 4-6 of rigidity_table.hpp on a set of
// pose frames, shared by the builder's nominal and perturbed evaluations.
#pragma once

#include <cstddef>

#include "trueaxis/core/rigidity_table.hpp"

namespace trueaxis::core::detail {

// E = [x, n x x, n] (columns).
Mat3 frame_axes(const Vec3& x_axis, const Vec3& normal);

// The A-axis circle, theta, theory frames, rotation vectors, A errors, origin
// offsets and C-to-A errors of `count` poses sorted by A, `reference` the index
// of the pose at A = 0. kAAxisUndetermined when the A-axis circle fit fails.
// The A-axis circle's points and fit go to `work` (its frames may be `poses`).
[[nodiscard]] Status evaluate_rigidity(const RigidityPoseFrame* poses, std::size_t count, std::size_t reference,
                                       double min_a_arc_deg, RigidityEvaluation& out, RigidityScratch& work);

}  // namespace trueaxis::core::detail
