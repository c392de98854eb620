// trueaxis-calibrate METHOD --in SAMPLES.csv --json OUT.json [--machine MACHINE.csv]
//                   [--report DIR] [--store] [--port PORT] [--host ADDR] [--unlock-code CODE]
// The integrator's command (INTERFACE.md, "The integrator's command"): reads the
// samples, streams them to the module over Modbus (default 127.0.0.1:502), runs
// the method's macros there and writes what the module computed into OUT.json;
// --report DIR also writes DIR/index.html with plots; --store stores the result
// as the controller's calibration table (unlocking with --unlock-code, default
// the published 2718, and locking again).
// Exit 0 on success; 1 with one line on stderr on any failure, and then no
// OUT.json, no report and nothing stored.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <unistd.h>

#include <cerrno>
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "trueaxis/sim/tools/calibrate.hpp"

namespace {

using trueaxis::sim::CalibrateOptions;
using trueaxis::sim::FlowResult;

int usage(const char* why) {
  std::fprintf(stderr,
               "trueaxis-calibrate: %s\n"
               "usage: trueaxis-calibrate rigidity|gantry|spindle --in SAMPLES.csv --json OUT.json\n"
               "       [--machine MACHINE.csv] [--report DIR] [--store] [--port PORT] [--host ADDR]\n"
               "       [--unlock-code CODE]   the machine's unlock code for --store (default 2718)\n",
               why);
  return 1;
}

int fail(const std::string& line) {
  std::fprintf(stderr, "trueaxis-calibrate: %s\n", line.c_str());
  return 1;
}

bool write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  return static_cast<bool>(out << text) && static_cast<bool>(out.flush());
}

// Runs Debian's python3 (where python3-matplotlib installs, whatever else is
// first on PATH) on the report script with argv, no shell; true on exit 0.
// Its stderr goes nowhere: a failure is the command's one line.
bool make_report(const CalibrateOptions& o, const std::string& json_path) {
  const std::string script = TRUEAXIS_REPORT_SCRIPT;
  const char* args[] = {TRUEAXIS_PYTHON, script.c_str(), o.method.c_str(), json_path.c_str(),
                        o.report_dir.c_str(), nullptr};
  posix_spawn_file_actions_t quiet;
  posix_spawn_file_actions_init(&quiet);
  posix_spawn_file_actions_addopen(&quiet, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, TRUEAXIS_PYTHON, &quiet, nullptr, const_cast<char* const*>(args), environ);
  posix_spawn_file_actions_destroy(&quiet);
  if (spawned != 0) return false;
  int status = 0;
  return waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

FlowResult calibrate(trueaxis::sim::VariableClient& client, const CalibrateOptions& o) {
  if (o.method == "gantry") return trueaxis::sim::calibrate_gantry(client, o);
  if (o.method == "spindle") return trueaxis::sim::calibrate_spindle(client, o);
  return trueaxis::sim::calibrate_rigidity(client, o);
}

bool store(trueaxis::sim::VariableClient& client, const std::string& method, FlowResult& r) {
  if (method == "gantry") return trueaxis::sim::store_gantry(client, r);
  if (method == "spindle") return trueaxis::sim::store_spindle(client, r);
  return trueaxis::sim::store_rigidity(client, r);
}

}  // namespace

int main(int argc, char** argv) {
  CalibrateOptions o;
  if (argc < 2) return usage("no METHOD");
  o.method = argv[1];
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--store") {
      o.store = true;
    } else if (arg == "--in" && has_value) {
      o.in_path = argv[++i];
    } else if (arg == "--json" && has_value) {
      o.json_path = argv[++i];
    } else if (arg == "--machine" && has_value) {
      o.machine_path = argv[++i];
    } else if (arg == "--report" && has_value) {
      o.report_dir = argv[++i];
    } else if (arg == "--unlock-code" && has_value) {
      char* end = nullptr;
      const long code = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || code < 1 || code > 9999) return usage("--unlock-code takes 1..9999");
      o.unlock_code = static_cast<double>(code);
    } else if (arg == "--host" && has_value) {
      o.host = argv[++i];
    } else if (arg == "--port" && has_value) {
      char* end = nullptr;
      const long port = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || port < 1 || port > 65535) return usage("--port takes 1..65535");
      o.port = static_cast<int>(port);
    } else {
      return usage(("unknown or incomplete option '" + arg + "'").c_str());
    }
  }
  if (o.in_path.empty() || o.json_path.empty()) return usage("--in and --json are required");
  if (o.method != "rigidity" && o.method != "gantry" && o.method != "spindle") {
    return usage(("unknown METHOD '" + o.method + "'").c_str());
  }

  trueaxis::sim::VariableClient client;
  if (!client.connect(o.host, o.port)) {
    return fail("cannot connect to " + o.host + ":" + std::to_string(o.port) + ": " + client.error_text());
  }
  FlowResult r = calibrate(client, o);
  if (!r.ok) return fail(r.error);

  // OUT.json goes to a temporary file first and into place last, after the
  // report and the store: on any failure it is absent and nothing is stored.
  const std::string tmp = o.json_path + ".tmp";
  const auto fail_clean = [&tmp](const std::string& line) {
    std::remove(tmp.c_str());
    return fail(line);
  };
  if (!write_file(tmp, r.json)) return fail_clean(o.json_path + ": cannot be written");
  if (!o.report_dir.empty()) {
    struct stat st {};
    if ((::mkdir(o.report_dir.c_str(), 0755) != 0 && errno != EEXIST) || ::stat(o.report_dir.c_str(), &st) != 0 ||
        !S_ISDIR(st.st_mode) || !write_file(o.report_dir + "/module_figures.json", r.report_extras) ||
        !make_report(o, tmp)) {
      return fail_clean(o.report_dir + ": the report could not be made (" TRUEAXIS_PYTHON " " TRUEAXIS_REPORT_SCRIPT ")");
    }
  }
  r.unlock_code = o.unlock_code;
  if (o.store && !store(client, o.method, r)) {
    return fail_clean(r.error);
  }
  client.close();
  if (std::rename(tmp.c_str(), o.json_path.c_str()) != 0) return fail_clean(o.json_path + ": cannot be written");
  return 0;
}
