// What every host program in build/host/bin answers to --help and --version,
// the product's commands and the benches alike (tests/sim/tools/test_commands.py
// runs them all).
//
// Contract
//  1. version_line(name) is "NAME VERSION (interface N, source REV)": VERSION
//     the CMake project version, N the register map's interface version
//     (macros::kInterfaceVersionValue, #9006), REV `git describe --always
//     --dirty` of the source tree, taken at every build (source_revision.cmake),
//     "unknown" when the tree is not a git checkout.
//  2. answered_help_or_version(argc, argv, name, help): when an argument is
//     --help or -h, prints `help` on stdout; when it is --version, the version
//     line; whichever comes first. It returns true then, and the caller exits
//     0; otherwise false, having printed nothing.
//  3. A help text starts with "usage: NAME ..." and ends with a newline.
//  4. finite_number(text, out): the whole of `text` read as C's strtod reads
//     it, and finite; false (out unspecified) otherwise.
//  5. write_text_file(path, text): `path` holds exactly `text` (created or
//     truncated, bytes as they are); false when it could not be written.
#pragma once

#include <string>

namespace trueaxis::sim {

// Contract 1: the parts, and the line.
const char* product_version();
const char* source_revision();
int interface_version();
std::string version_line(const char* name);

// Contract 2.
bool answered_help_or_version(int argc, char** argv, const char* name, const char* help);

// Contract 4.
bool finite_number(const char* text, double& out);

// Contract 5.
bool write_text_file(const std::string& path, const std::string& text);

}  // namespace trueaxis::sim
