// The spindle method's calibrate flow (calibrate.hpp: its entry is
// calibrate_method_spindle(), host_methods.hpp), for the command and the tests.
#pragma once

#include <string>

#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/client.hpp"

namespace trueaxis::sim {

// The spindle angles of OUT.json's per_angle: 0, 5, ..., 355 (docs/INTERFACE.md: at most 10).
inline constexpr double kSpindleStepDeg = 5.0;

// Streams the analyser samples (file order) to the session 9840/9841,
// identifies the tool-axis model with 9842 WITHOUT storing it (D, U, V from
// MACHINE), and reads back the parameters (9845, R = 0) and one revolution of
// the correction with its sigmas at tool_length_mm (9844, R = 0, every
// kSpindleStepDeg). OUT.json adds to docs/INTERFACE.md's keys the per-angle
// sigmas, tool_length_mm, the mean tool-tip error over a revolution with its
// sigma, and "fit" (samples, noise, synchronous and overall RMS).
// MACHINE holds `name,value` rows: exactly the five names docs/INTERFACE.md
// requires, each once; any other name is refused (there are no optional names
// yet, and a misspelt one would otherwise pass unnoticed). bearing_spacing_mm,
// which the model does not take (the analyser sees the tool line, not the
// bearings), is only checked (> 0) and shown in the report. A ball other than
// 1 or 2 is refused at its line; a length the module refuses names MACHINE.
FlowResult calibrate_spindle(VariableClient& client, const CalibrateOptions& options);

// Stores the model of the session already in the module (unlock, 9842 with
// result.build_arguments and R = 1, lock again).
bool store_spindle(VariableClient& client, FlowResult& result);


// The LinuxCNC kinematics' spindle file: the model identified last (stored
// false: 9847 R = 0) or the stored one (true), its record read exactly
// through macro 9847, as record_file.hpp's file of the spindle record.
bool spindle_kins_file(VariableClient& client, bool stored, std::string& file, FlowResult& fail);

}  // namespace trueaxis::sim
