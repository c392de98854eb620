// The simulator's own variables #12000..#12047 (sim_map.hpp) over a virtual
// cradle machine (machines/cradle_machine.hpp) and its instruments (the touch
// probe, the calibration ball): moving the table, probing the face, measuring
// the ball, switching the machine's geometric errors, and the ground truth.
//
// Contract
//  1. A VariableAccess for exactly the numbers of kSimMap; any other number is
//     kUndefined. Reads and writes are whole or nothing, like the module's.
//  2. Write checks, in order: access (read-only -> kReadOnly), then each value
//     against its kSimMap entry (check_value: kNotFinite, kOutOfRange). Then the
//     variables are applied in ascending order on a copy of the state, so a write
//     of #12000..#12004 moves the table and the probe before it probes.
//  3. Writing sim_probe_into (#12004) = T probes: the probe comes down at
//     (sim_probe_x, sim_probe_y) with the table at (sim_axis_a, sim_axis_c), adds
//     noise of sim_probe_sigma per coordinate, and writes X, Y, Z into #T, #T+1,
//     #T+2 through `target` (the module), so the module validates and stores them
//     as if a client had written them. T must be a work offset's X (5221, 5241,
//     .., 5321) or a point-list X (1001, 1004, .., 1094): otherwise kOutOfRange.
//     The face too steep to touch (touch_probe.hpp convention 1) is
//     kOutOfRange. A fault from `target` is returned as is. On any fault nothing
//     changes: no variable here, nothing in the module, and no noise is drawn.
//  4. Writing sim_ball_measure (#12025) = 1 measures the ball (centre
//     sim_ball_x, _y, _z in table coordinates) with the table at (sim_axis_a,
//     sim_axis_c), adding noise of sim_ball_sigma per coordinate, into
//     sim_last_ball_x, _y, _z; 0 measures nothing. Every variable of the same write
//     (the table, the ball, sim_errors) applies before it measures. It always
//     succeeds and always draws three deviates.
//  5. sim_errors (#12020): 0 the ideal machine (CradleErrors{}), 1 the machine with
//     the errors given to the constructor (realistic_errors() by default), both
//     about the constructor's nominal pivot. The
//     probe, the ball and every ground-truth read-back follow the present value;
//     the truth that depends on a ball height (rotation vector, A positioning
//     error, C centre) is for a ball at sim_ball_z.
//  7. sim_drift_a, sim_drift_arcsec (#12055, #12056): a rigidity the machine
//     with errors adds at exactly that commanded A (CradleErrors local_a_deg,
//     local_arcsec: a clamp worked loose at that tilt), for scripting a drift
//     between checks; 0 arcsec by default. Written, they apply from that write on.
//  6. after_request() is what the server calls after every request: it runs the
//     module's pending macro (Module::step) unless sim_hold (#12009) is 1.
#pragma once

#include <cstddef>
#include <cstdint>

#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/variable_access.hpp"
#include "trueaxis/sim/machines/cradle_machine.hpp"
#include "trueaxis/sim/machines/virtual_spindle.hpp"
#include "trueaxis/sim/server/sim_map.hpp"
#include "trueaxis/sim/sim_math.hpp"

namespace trueaxis::sim {

// True when T is a number sim_probe_into accepts (contract 3).
bool is_probe_target(double target);

class Simulator final : public macros::VariableAccess {
 public:
  // errors_on: the initial sim_errors (contract 5); errors: the set it turns on;
  // pivot: the cradle's nominal pivot, with and without the errors
  // (cradle_machine.hpp convention 1; the machine origin by default).
  Simulator(macros::Module& module, const FaceConfig& face, std::uint64_t seed, bool errors_on = false,
            const CradleErrors& errors = realistic_errors(), const CradlePivot& pivot = CradlePivot{});

  // Contract 6.
  void after_request();

  // The module behind the simulator, for what the transport owns: closing an
  // unlock when the connection that opened it closes (module.hpp contract 7).
  macros::Module& module() { return module_; }

  // The machine sim_errors selects now.
  const CradleMachine& machine() const { return machine_for(state_.values); }

  // The present value of #number, for number in kSimMap; 0 otherwise.
  double value(std::uint16_t number) const;

 private:
  static constexpr std::size_t kCount = simvar::kLast - simvar::kFirst + 1;

  struct State {
    double values[kCount] = {};
    SimRng rng{0};
  };

  macros::AccessFault do_read(std::uint16_t first, std::uint16_t count, double* out, macros::ClientId) override;
  macros::AccessFault do_write(std::uint16_t first, std::uint16_t count, const double* values, macros::ClientId client) override;
  void do_note_fault(macros::AccessFault) override {}

  macros::AccessFault probe(State& next, std::uint16_t target, macros::ClientId client);
  void measure_ball(State& next) const;
  double read_one(std::uint16_t number) const;
  const CradleMachine& machine_for(const double* values) const;
  // Contract 7: the machine with errors as `values` drift it.
  CradleMachine drifted(const double* values) const;

  macros::Module& module_;
  FaceConfig face_;
  CradleErrors errors_;
  CradlePivot pivot_;
  CradleMachine ideal_;
  CradleMachine with_errors_;
  VirtualSpindle spindle_;  // sim_spindle = 1: the realistic spindle
  State state_;
};

}  // namespace trueaxis::sim
