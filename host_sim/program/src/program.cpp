#include "trueaxis/sim/program.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "trueaxis/macros/platform_map.hpp"

namespace trueaxis::sim {

// Defined in the source file source_revision.cmake writes at build time.
extern const char* const kSourceRevision;

const char* product_version() { return TRUEAXIS_VERSION; }

const char* source_revision() { return kSourceRevision; }

int interface_version() { return static_cast<int>(macros::kInterfaceVersionValue); }

std::string version_line(const char* name) {
  return std::string(name) + " " + product_version() + " (interface " + std::to_string(interface_version()) +
         ", source " + source_revision() + ")";
}

bool answered_help_or_version(int argc, char** argv, const char* name, const char* help) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::fputs(help, stdout);
      return true;
    }
    if (std::strcmp(argv[i], "--version") == 0) {
      std::printf("%s\n", version_line(name).c_str());
      return true;
    }
  }
  return false;
}

bool finite_number(const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(out);
}

bool write_text_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  return out && (out << text) && out.flush();
}

}  // namespace trueaxis::sim
