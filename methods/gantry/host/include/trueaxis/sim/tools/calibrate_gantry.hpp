// The gantry method's calibrate flow (calibrate.hpp: its entry is
// calibrate_method_gantry(), host_methods.hpp), for the command and the tests.
#pragma once

#include <string>

#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/client.hpp"

namespace trueaxis::sim {

// Streams the tracker points (grouped by name, measuring order kept) and the
// MACHINE rows, computes the frames WITHOUT storing them; reads back what the
// module computed (9824, 9826). Every sub-machine SAMPLES measures needs its
// MACHINE row, and every MACHINE row its points: a row whose sub-machine has
// no points is refused at its line (a sub-machine forgotten, or its groups
// misnamed), unless options.sub_machines names the ones measured (one
// sub-machine measured again with the whole machine's MACHINE file); then
// the others' rows are not read, and a point of another is refused.
FlowResult calibrate_gantry(VariableClient& client, const CalibrateOptions& options);

// Stores the frames of the session already in the module (unlock, 9823 with
// R = 1, lock again).
bool store_gantry(VariableClient& client, FlowResult& fail);

}  // namespace trueaxis::sim
