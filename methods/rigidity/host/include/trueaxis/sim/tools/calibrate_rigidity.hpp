// The rigidity method's calibrate flow (calibrate.hpp: its entry is
// calibrate_method_rigidity(), host_methods.hpp), for the command and the tests.
#pragma once

#include <string>

#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/client.hpp"

namespace trueaxis::sim {

// Streams the samples and builds the table WITHOUT storing it; reads back
// what the module computed.
FlowResult calibrate_rigidity(VariableClient& client, const CalibrateOptions& options);

// Stores the table of the samples already in the module's session (unlock,
// build with R = 1, lock again); false with fail.error set otherwise.
bool store_rigidity(VariableClient& client, FlowResult& fail);

// The LinuxCNC kinematics' table file (integrations/linuxcnc/kins): the table
// built last (stored false: 9837 R = 0) or the stored one (true), read exactly
// through macro 9837, as record_file.hpp's file of the rigidity record; false
// with fail.error set otherwise.
bool rigidity_kins_file(VariableClient& client, bool stored, std::string& file, FlowResult& fail);

}  // namespace trueaxis::sim
