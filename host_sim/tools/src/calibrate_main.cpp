// trueaxis-calibrate METHOD --in SAMPLES.csv --json OUT.json [--machine MACHINE.csv]
//                   [--report DIR] [--store] [--port PORT] [--host ADDR] [--unlock-code CODE]
//                   [--accept-change] [--wait SECONDS] [--linuxcnc-comp FILE] [--linuxcnc-kins FILE]
//                   [--check] [--operator NAME] [--machine-name NAME] [--time WHEN]
//                   [--sub-machines N,N...]
// trueaxis-calibrate log [--port PORT] [--host ADDR] [--csv FILE] [--wait SECONDS]
// trueaxis-calibrate plan METHOD [PLAN OPTIONS] [--json PLAN.json] [--suggest N]
// trueaxis-calibrate linuxcnc-kins METHOD --out FILE [--port PORT] [--host ADDR] [--wait SECONDS]
// trueaxis-calibrate linuxcnc-trt rigidity --out FILE.hal [--port PORT] [--host ADDR] [--wait SECONDS]
// The integrator's command (docs/INTERFACE.md, "The integrator's command"):
// reads the samples, streams them to the module over Modbus (default
// 127.0.0.1:502), runs the method's macros there and writes what the module
// computed into OUT.json; --report DIR also writes DIR/index.html with plots;
// --store stores the result as the controller's calibration table (unlocking
// with --unlock-code, default the published 2718, and locking again). The
// methods are the table of calibrate.hpp and their plans the table of
// plan_options.hpp, folds over the one list (host_methods.hpp); this file names
// none of them but in `linuxcnc-trt rigidity`, M3's table as xyzac-trt-kins'
// pivot (trt_export.hpp, methods/rigidity/host).
// Exit 0 with one summary line on stdout: what was computed, the worst figure
// with its sigma, what was written and what stored. Exit 1 with one line on
// stderr on any failure, bad usage included, and then nothing on stdout, no
// OUT.json, no report and nothing stored (both are made in temporaries beside
// their targets, DIR.tmp-XXXXXX and OUT.json.tmp, and moved into place after
// the store). Work over 2 s reports its progress on stderr first. The module
// grants its macro interface to one client at a time (macros/module.hpp
// contract 8): while another client holds it, the command says so on stderr
// and waits, at most --wait seconds (default 120), then fails with that
// sentence. --check compares the result with the stored calibration instead
// of storing it (check.hpp): OUT.json gains a "check" object, and the command
// exits 3 when the verdict is fail (0 on pass or warn). Each build, store and
// check hands the module the time for its measuring log (--time, default
// now); `log` prints that log, newest last, with the drift of every checked
// figure, and --csv writes it as CSV. `plan` predicts, before measuring, the
// 1-sigma of every output of a planned measurement (planner.hpp): it needs no
// module, it runs the method's own routine on the simulator's machine.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <dirent.h>
#include <fcntl.h>
#include <ftw.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "trueaxis/sim/program.hpp"
#include "trueaxis/sim/tools/calibrate.hpp"
#include "trueaxis/sim/tools/csv.hpp"
#include "trueaxis/sim/tools/log_reader.hpp"
#include "trueaxis/sim/tools/host_methods.hpp"
#include "trueaxis/sim/tools/plan_options.hpp"
#include "trueaxis/sim/tools/planner.hpp"
#include "trueaxis/sim/tools/trt_export.hpp"

using trueaxis::sim::write_text_file;

namespace {

using trueaxis::sim::CalibrateMethod;
using trueaxis::sim::CalibrateOptions;
using trueaxis::sim::FlowResult;

constexpr const char* kUsage =
    "usage: trueaxis-calibrate METHOD --in SAMPLES.csv --json OUT.json [--machine MACHINE.csv]\n"
    "                          [--report DIR] [--store] [--port PORT] [--host ADDR] [--unlock-code CODE]\n"
    "                          [--accept-change] [--wait SECONDS] [--linuxcnc-comp FILE] [--linuxcnc-kins FILE]\n"
    "                          [--check] [--operator NAME] [--machine-name NAME] [--time WHEN]\n"
    "                          [--sub-machines N,N...]\n"
    "       trueaxis-calibrate log [--port PORT] [--host ADDR] [--csv FILE] [--wait SECONDS]\n"
    "       trueaxis-calibrate plan METHOD [PLAN OPTIONS] [--json PLAN.json] [--suggest N]\n"
    "       trueaxis-calibrate linuxcnc-kins METHOD --out FILE [--port PORT] [--host ADDR] [--wait SECONDS]\n"
    "       trueaxis-calibrate linuxcnc-trt rigidity --out FILE.hal [--port PORT] [--host ADDR] [--wait SECONDS]\n";

constexpr const char* kPlanHelp =
    "plan METHOD: the 1-sigma of every output of a planned measurement, predicted before it is\n"
    "made from the method's own computation (the module's firmware_core routine, linearised about\n"
    "the instrument's noise-free readings of the simulator's machine), the plan's valuation (the\n"
    "worst 2 sigma / check tolerance), the outputs it cannot separate (|correlation| > 0.99), and the\n"
    "one or two changes of about one pose that lower the valuation most. No module is needed.\n"
    ;

// After the methods' options in `plan --help`.
constexpr const char* kPlanHelpEnd =
    "  --json PLAN.json  the prediction as JSON; --suggest N  0..2 changes to look for (2)\n"
    "Exit 0 with the prediction on stdout; 3 when the method would refuse the plan (stdout and\n"
    "PLAN.json say why, as the module's error); 1 on bad usage or an unwritable PLAN.json.\n";

int fail(const std::string& line) {
  std::fprintf(stderr, "trueaxis-calibrate: %s\n", line.c_str());
  return 1;
}

int usage_error(const std::string& why) { return fail(why + " (trueaxis-calibrate --help)"); }

// Runs Debian's python3 (where python3-matplotlib installs, whatever else is
// first on PATH) on the report script with argv, no shell; true on exit 0.
// Its stderr goes nowhere: a failure is the command's one line.
bool make_report(const CalibrateMethod& method, const std::string& dir, const std::string& json_path) {
  const std::string script = TRUEAXIS_REPORT_SCRIPT;
  const char* args[] = {TRUEAXIS_PYTHON, script.c_str(), method.report_module, json_path.c_str(), dir.c_str(),
                        nullptr};
  posix_spawn_file_actions_t quiet;
  posix_spawn_file_actions_init(&quiet);
  posix_spawn_file_actions_addopen(&quiet, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&quiet, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, TRUEAXIS_PYTHON, &quiet, nullptr, const_cast<char* const*>(args), environ);
  posix_spawn_file_actions_destroy(&quiet);
  if (spawned != 0) return false;
  int status = 0;
  return waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// The JSON register map of this build (trueaxis-map --json) into `path`, for
// the report's record: the map the report was made with, and its hash.
bool write_map(const std::string& path) {
  const char* args[] = {TRUEAXIS_MAP_BINARY, "--json", nullptr};
  posix_spawn_file_actions_t out;
  posix_spawn_file_actions_init(&out);
  posix_spawn_file_actions_addopen(&out, 1, path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&out, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, TRUEAXIS_MAP_BINARY, &out, nullptr, const_cast<char* const*>(args), environ);
  posix_spawn_file_actions_destroy(&out);
  if (spawned != 0) return false;
  int status = 0;
  return waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// True when `text` is UTF-8 without control characters (an --operator NAME):
// neither C0 (U+0000..U+001F), DEL nor C1 (U+0080..U+009F, C2 80..C2 9F).
bool printable_utf8(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    const std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    if (n == 0 || c < 0x20 || c == 0x7F || i + n > text.size()) return false;
    for (std::size_t k = 1; k < n; ++k) {
      if ((static_cast<unsigned char>(text[i + k]) >> 6) != 0x2) return false;
    }
    if (c == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0) return false;
    i += n;
  }
  return true;
}

std::string plan_help();

void print_help() {
  std::printf("%s\n", kUsage);
  std::printf("Calibrates in the module over Modbus TCP and writes what it computed into OUT.json.\n"
              "METHOD (trueaxis-calibrate METHOD --help: its files' columns and units):\n");
  for (const CalibrateMethod& m : trueaxis::sim::calibrate_methods()) std::printf("  %-9s %s\n", m.name, m.title);
  std::printf("\n"
              "  --in SAMPLES.csv       the measurements (required)\n"
              "  --json OUT.json        where the result goes (required)\n"
              "  --machine MACHINE.csv  the machine's nominal data (gantry, spindle)\n"
              "  --sub-machines N,N...  gantry: the sub-machines this session measures (MACHINE's other\n"
              "                         rows are not read); without it every MACHINE row needs its points\n"
              "  --report DIR           also DIR/index.html with plots (DIR made if absent)\n"
              "  --store                store the result as the controller's calibration table:\n"
              "                         unlock, store, lock again\n"
              "  --port PORT, --host ADDR  the module's Modbus TCP server (default 127.0.0.1:502)\n"
              "  --unlock-code CODE     the machine's unlock code (#900) for --store, 1..9999 (default 2718)\n"
              "  --linuxcnc-comp FILE   rigidity, with --store: also the stored A positioning error as a\n"
              "                         LinuxCNC joint compensation file for the A joint (COMP_FILE_TYPE = 1);\n"
              "                         not with --linuxcnc-kins, whose table corrects A itself\n"
              "  --linuxcnc-kins FILE   rigidity or spindle, with --store: also the stored table or model as\n"
              "                         the file the LinuxCNC kinematics trueaxis_kins load (integrations/linuxcnc/kins)\n"
              "  --accept-change        with --store: store even a result that differs from the stored\n"
              "                         calibration by more than the method's change limit (its build\n"
              "                         macro's M = 1); check the machine first\n"
              "  --check                compare with the stored calibration instead of storing: OUT.json's\n"
              "                         \"check\" holds every stored figure's deviation with its sigma and a\n"
              "                         verdict (pass, warn, fail) against the tolerances configured in the\n"
              "                         module; exit 3 on fail\n"
              "  --operator NAME        who measured: shown in the report\n"
              "  --machine-name NAME    the machine's name, letters and all: shown in the report beside\n"
              "                         its number #902 (the module holds numbers only)\n"
              "  --time WHEN            when it was measured, for the module's measuring log: Unix seconds,\n"
              "                         or UTC as 2027-01-15, 2027-01-15T08:00:00Z (default now)\n"
              "  --wait SECONDS         how long to wait while another client holds the controller's\n"
              "                         macro interface, 0..3600 (default 120)\n"
              "  --help, --version      this text (METHOD --help: the method's files); the version line\n"
              "log: the module's measuring log (every calibration, store and check of M2, M3, M4), newest\n"
              "last, and per checked figure its drift (a weighted line through its deviations) with the\n"
              "date it reaches its tolerance; --csv FILE writes the entries as CSV too.\n"
              "linuxcnc-kins METHOD: the controller's stored M3 table (rigidity) or M4 model (spindle) as\n"
              "the file the LinuxCNC kinematics trueaxis_kins load (integrations/linuxcnc/kins).\n"
              "linuxcnc-trt rigidity: the controller's stored M3 table as LinuxCNC's own xyzac-trt-kins'\n"
              "pivot (setp lines of x/y/z-rot-point and y/z-offset, a HAL file), what those cannot hold\n"
              "(the axes' directions, the rigidity, the A positioning error) stated in it and on stdout.\n"
              "%s"
              "Exit 0 with one summary line on stdout; 1 with one line on stderr on any failure, and\n"
              "then no OUT.json and nothing stored; 3 when --check's verdict is fail (OUT.json and the\n"
              "report written).\n", plan_help().c_str());
}

void print_method_help(const CalibrateMethod& m) {
  std::printf("trueaxis-calibrate %s: %s\n\n%s\n%s\n", m.name, m.title, kUsage, m.files);
  std::printf("CSV: a header row, columns in any order (others ignored); '#' lines are comments;\n"
              "a field may be in double quotes (\"x_mm\", \"1.5\"); numbers as C strtod reads them, with '.'\n"
              "as the decimal sign (not NaN or infinite).\n");
}

// ---- the outputs, tried before the work -------------------------------------------------

// The folder that holds `path` ("." for a bare name).
std::string parent_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// Why a file cannot be made in folder `dir`, "" when it can: it is tried (a
// hidden file made there and removed at once).
std::string folder_cause(const std::string& dir) {
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0) {
    const int error = errno;
    if (error == ENOENT || error == ENOTDIR) {
      // The first part of the path that is missing, or a file where a folder is wanted.
      for (std::size_t at = dir.find('/', 1);; at = dir.find('/', at + 1)) {
        const std::string part = dir.substr(0, at);
        struct stat p {};
        if (::stat(part.c_str(), &p) != 0) return "no such directory '" + part + "'";
        if (!S_ISDIR(p.st_mode)) return "'" + part + "' is a file, where a folder is wanted";
        if (at == std::string::npos) break;
      }
    }
    return "'" + dir + "': " + std::strerror(error);
  }
  if (!S_ISDIR(st.st_mode)) return "'" + dir + "' is a file, where a folder is wanted";
  std::string probe = dir + "/.trueaxis-calibrate-XXXXXX";
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) {
    const int error = errno;
    if (error == EROFS) return "'" + dir + "' is on a read-only file system";
    if (error == EACCES || error == EPERM) return "'" + dir + "' is read-only: no permission to write in it";
    return "'" + dir + "': " + std::strerror(error);
  }
  ::close(fd);
  ::unlink(probe.c_str());
  return "";
}

// Why the file `path` cannot be written (made beside it as PATH.tmp, then
// renamed over it), "" when it can.
std::string file_cause(const std::string& path) {
  if (path.empty() || path.back() == '/') return "a file name is wanted, not a folder";
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) return "it is a folder, where a file is wanted";
  return folder_cause(parent_of(path));
}

// Why the report folder `dir` cannot be made or filled, "" when it can: made
// beside itself (DIR.tmp-XXXXXX, its parent) and moved into place (into DIR
// when it exists).
std::string report_cause(std::string dir) {
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  struct stat st {};
  if (::stat(dir.c_str(), &st) == 0) {
    if (!S_ISDIR(st.st_mode)) return "'" + dir + "' is a file, where a folder is wanted";
    const std::string in_dir = folder_cause(dir);
    if (!in_dir.empty()) return in_dir;
  }
  return folder_cause(parent_of(dir));
}

// "PATH: cannot be written (CAUSE)": the cause as it stands now, or errno's.
std::string cannot_write(const std::string& path, int error = 0) {
  std::string cause = file_cause(path);
  if (cause.empty()) cause = error != 0 ? std::strerror(error) : "the write failed";
  return path + ": cannot be written (" + cause + ")";
}

int remove_entry(const char* path, const struct stat*, int, struct FTW*) { return std::remove(path); }

// A directory and all it holds.
void remove_tree(const std::string& dir) {
  if (!dir.empty()) ::nftw(dir.c_str(), remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

// The report made in `tmp` into its place `dir`: renamed when `dir` does not
// exist, else each file moved into it (a report made earlier is replaced file
// by file); true when all moved.
bool place_report(const std::string& tmp, const std::string& dir) {
  if (::rename(tmp.c_str(), dir.c_str()) == 0) return true;
  DIR* d = ::opendir(tmp.c_str());
  if (d == nullptr) return false;
  bool moved = true;
  while (const dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name == "." || name == "..") continue;
    moved = moved && ::rename((tmp + "/" + name).c_str(), (dir + "/" + name).c_str()) == 0;
  }
  ::closedir(d);
  remove_tree(tmp);
  return moved;
}

// "; stored (record 3 rigidity_table)".
std::string stored_text(const char* method) {
  const trueaxis::macros::RecordSpec* spec = trueaxis::sim::stored_record(method);
  return spec != nullptr ? "stored (record " + std::to_string(spec->key) + " " + spec->name + ")" : "stored";
}

// The report's record (host_sim/report/trueaxis_report.py): who, when, with
// what, the verdict; added to the module's figures beyond OUT.json.
std::string with_record(const std::string& extras, const CalibrateOptions& o, const std::string& verdict,
                        double machine_id, double interface_version) {
  using trueaxis::sim::json_string;
  char when[64];
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%S%z", &local);
  std::string inputs = json_string(o.in_path);
  if (!o.machine_path.empty()) inputs += ", " + json_string(o.machine_path);
  const std::string record =
      "\"record\": { \"verdict\": " + json_string(verdict) + ", \"date\": " + json_string(when) +
      ", \"version\": " + json_string(trueaxis::sim::version_line("trueaxis-calibrate")) +
      ", \"interface_version\": " + trueaxis::sim::json_number(interface_version) + ", \"machine_id\": " +
      trueaxis::sim::json_number(machine_id) + ", \"machine_name\": " + json_string(o.machine_name) +
      ", \"operator\": " + json_string(o.operator_name) + ", \"inputs\": [" + inputs + "], \"out_json\": " +
      json_string(o.json_path) + ", \"report_dir\": " + json_string(o.report_dir) +
      ", \"register_map\": \"register_map.json\" }";
  return trueaxis::sim::with_member(extras, record);
}

// --time WHEN: Unix seconds, or a UTC date and time; 0 when it is neither.
double parse_time(const std::string& text) {
  char* end = nullptr;
  const double seconds = std::strtod(text.c_str(), &end);
  if (!text.empty() && *end == '\0') return seconds >= 1.0 && seconds <= 4294967295.0 ? std::floor(seconds) : 0.0;
  for (const char* format : {"%Y-%m-%dT%H:%M:%SZ", "%Y-%m-%dT%H:%M:%S", "%Y-%m-%d %H:%M:%S", "%Y-%m-%d"}) {
    std::tm t{};
    const char* rest = ::strptime(text.c_str(), format, &t);
    if (rest == nullptr || *rest != '\0') continue;
    const std::time_t s = ::timegm(&t);
    return s >= 1 && s <= 4294967295 ? static_cast<double>(s) : 0.0;
  }
  return 0.0;
}

// The module's address and how long to wait for its macro interface, as
// `log` and `linuxcnc-kins` take them (--host, --port, --wait).
struct Connection {
  std::string host = "127.0.0.1";
  int port = 502;
  int wait_s = 120;

  // argv[i] if it is one of the three (its value consumed): 1; not one: 0;
  // one with a bad value: -1 with `error` the usage line.
  int parse(int argc, char** argv, int& i, std::string& error) {
    const std::string arg = argv[i];
    if (i + 1 >= argc || (arg != "--host" && arg != "--port" && arg != "--wait")) return 0;
    const char* value = argv[++i];
    if (arg == "--host") {
      host = value;
      return 1;
    }
    char* end = nullptr;
    const long v = std::strtol(value, &end, 10);
    if (arg == "--port") {
      if (*end != '\0' || v < 1 || v > 65535) return error = "--port takes 1..65535", -1;
      port = static_cast<int>(v);
    } else {
      if (*end != '\0' || v < 0 || v > 3600) return error = "--wait takes 0..3600 (seconds)", -1;
      wait_s = static_cast<int>(v);
    }
    return 1;
  }

  // Connects and takes the macro interface, waiting up to wait_s while another
  // client holds it; "" or the one line that says why not.
  std::string open(trueaxis::sim::VariableClient& client) const {
    if (!client.connect(host, port)) {
      return "cannot connect to " + host + ":" + std::to_string(port) + ": " + client.error_text();
    }
    const std::string busy = "controller busy: another client holds the macro interface";
    const int wait = wait_s;
    const bool taken = client.take_interface(wait * 1000, [&busy, wait] {
      std::fprintf(stderr, "trueaxis-calibrate: %s, waiting (up to %d s)\n", busy.c_str(), wait);
    });
    if (taken) return "";
    const std::string why = client.failure_text();
    return why == busy ? busy + " (waited " + std::to_string(wait) + " s; --wait SECONDS)" : why;
  }
};

// trueaxis-calibrate log [--port PORT] [--host ADDR] [--csv FILE] [--wait SECONDS].
int run_log(int argc, char** argv) {
  Connection connection;
  std::string csv_path;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    std::string error;
    const int parsed = connection.parse(argc, argv, i, error);
    if (parsed < 0) return usage_error(error);
    if (parsed > 0) continue;
    if (arg == "--help" || arg == "-h") {
      print_help();
      return 0;
    } else if (arg == "--csv" && i + 1 < argc) {
      csv_path = argv[++i];
    } else {
      return usage_error("unknown or incomplete option '" + arg + "' for log");
    }
  }
  if (!csv_path.empty()) {  // tried before the module is asked
    const std::string cause = file_cause(csv_path);
    if (!cause.empty()) return fail(csv_path + ": cannot be written (" + cause + ")");
  }
  trueaxis::sim::VariableClient client;
  // Selecting an entry is a write to the macro interface (macros/module.hpp contract 8).
  const std::string why = connection.open(client);
  if (!why.empty()) return fail(why);
  std::vector<trueaxis::sim::LogRow> rows;
  std::string error;
  if (!trueaxis::sim::read_log(client, rows, error) || !trueaxis::sim::name_poses(client, rows, error)) {
    return fail(error);
  }
  client.give_back_interface();
  client.close();
  if (!csv_path.empty()) {
    const std::string tmp = csv_path + ".tmp";
    if (!write_text_file(tmp, trueaxis::sim::log_csv(rows)) || std::rename(tmp.c_str(), csv_path.c_str()) != 0) {
      const int write_error = errno;
      std::remove(tmp.c_str());
      return fail(cannot_write(csv_path, write_error));
    }
  }
  std::printf("%s", trueaxis::sim::log_table(rows, trueaxis::sim::fit_drift(rows)).c_str());
  return 0;
}


// trueaxis-calibrate linuxcnc-kins METHOD --out FILE [--port PORT] [--host ADDR] [--wait SECONDS]:
// the controller's stored M3 table or M4 model as the LinuxCNC kinematics'
// file, however it was stored (trueaxis-calibrate, an operator program's G65, an HMI).
// `trt`: linuxcnc-trt rigidity, the stored M3 table as xyzac-trt-kins' pivot
// (trt_export.hpp), a HAL file.
int run_kins_export(int argc, char** argv, bool trt) {
  const char* command = trt ? "linuxcnc-trt" : "linuxcnc-kins";
  Connection connection;
  std::string out_path;
  const CalibrateMethod* method = argc > 2 ? trueaxis::sim::find_calibrate_method(argv[2]) : nullptr;
  if (argc > 2 && (std::string(argv[2]) == "--help" || std::string(argv[2]) == "-h")) {
    print_help();
    return 0;
  }
  if (method == nullptr || method->kins_file == nullptr || (trt && std::string(method->name) != "rigidity")) {
    return usage_error(trt ? "linuxcnc-trt takes METHOD: rigidity" : "linuxcnc-kins takes METHOD: rigidity or spindle");
  }
  for (int i = 3; i < argc; ++i) {
    const std::string arg = argv[i];
    std::string error;
    const int parsed = connection.parse(argc, argv, i, error);
    if (parsed < 0) return usage_error(error);
    if (parsed > 0) continue;
    if (arg == "--help" || arg == "-h") {
      print_help();
      return 0;
    } else if (arg == "--out" && i + 1 < argc) {
      out_path = argv[++i];
    } else {
      return usage_error("unknown or incomplete option '" + arg + "' for " + command);
    }
  }
  if (out_path.empty()) return usage_error(std::string(command) + " needs --out FILE");
  const std::string cause = file_cause(out_path);  // tried before the module is asked
  if (!cause.empty()) return fail(out_path + ": cannot be written (" + cause + ")");
  trueaxis::sim::VariableClient client;
  const std::string why = connection.open(client);
  if (!why.empty()) return fail(why);
  std::string file;
  FlowResult r;
  const bool read = method->kins_file(client, true, file, r);
  client.give_back_interface();  // at once, whatever happened
  client.close();
  if (!read) return fail(r.error);
  trueaxis::sim::TrtParameters trt_p;
  if (trt) {
    trueaxis::core::RigidityTable table;
    std::string refused;
    if (!trueaxis::sim::decode_rigidity_file(file, table, refused) ||
        !trueaxis::sim::trt_parameters(table, trt_p, refused)) {
      return fail("linuxcnc-trt: " + refused);
    }
    file = trueaxis::sim::trt_hal_text(trt_p);
  }
  const std::string tmp = out_path + ".tmp";
  if (!write_text_file(tmp, file) || std::rename(tmp.c_str(), out_path.c_str()) != 0) {
    const int error = errno;
    std::remove(tmp.c_str());
    return fail(cannot_write(out_path, error));
  }
  if (trt) {
    std::printf("linuxcnc-trt: the stored rigidity table as xyzac-trt-kins' pivot (%.4f, %.4f, %.4f) mm, offsets "
                "Y %.4f Z %.4f mm; not held: %.2f\" (axes' directions, rigidity, A positioning error); wrote %s\n",
                trt_p.rot_point_mm.x(), trt_p.rot_point_mm.y(), trt_p.rot_point_mm.z(), trt_p.y_offset_mm,
                trt_p.z_offset_mm, trt_p.not_held_arcsec(), out_path.c_str());
    return 0;
  }
  std::printf("linuxcnc-kins: the stored %s calibration, %zu bytes; wrote %s\n", method->name, file.size(),
              out_path.c_str());
  return 0;
}

// `plan --help`: the command's text around each method's options (PlanOptions::help).
std::string plan_help() {
  std::string methods;
  for (const trueaxis::sim::PlanMethod& m : trueaxis::sim::kPlanMethods) methods += m.make()->help();
  return std::string(kPlanHelp) + methods + kPlanHelpEnd;
}

// trueaxis-calibrate plan METHOD [PLAN OPTIONS] [--json PLAN.json] [--suggest N]:
// the options are the method's (plan_options.hpp), but for --json and --suggest.
int run_plan(int argc, char** argv) {
  namespace ts = trueaxis::sim;
  std::vector<const char*> plan_names;
  for (const ts::PlanMethod& m : ts::kPlanMethods) plan_names.push_back(m.name);
  const std::string names = ts::spoken_list(plan_names);
  if (argc < 3) return usage_error("plan takes METHOD: " + names);
  const std::string method = argv[2];
  if (method == "--help" || method == "-h") {
    std::printf("%s\n%s", kUsage, plan_help().c_str());
    return 0;
  }
  std::unique_ptr<ts::PlanOptions> options;
  for (const ts::PlanMethod& m : ts::kPlanMethods) {
    if (method == m.name) options = m.make();
  }
  if (options == nullptr) return usage_error("plan: unknown METHOD '" + method + "' (" + names + ")");
  std::string json_path;
  int suggest = 2;
  for (int i = 3; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has = i + 1 < argc;
    const std::string value = has ? argv[i + 1] : "";
    std::string form = "a value";
    bool ok = has;
    if (arg == "--help" || arg == "-h") {
      std::printf("%s\n%s", kUsage, plan_help().c_str());
      return 0;
    } else if (arg == "--json") {
      json_path = value;
      ok = ok && !value.empty();
    } else if (arg == "--suggest") {
      form = "0, 1 or 2";
      ok = ok && ts::plan_whole(value, 0, 2, suggest);
    } else {
      const ts::PlanOptions::Take take = options->take(arg, value, has, form);
      if (take == ts::PlanOptions::Take::kNotMine) return usage_error("unknown option '" + arg + "' for plan " + method);
      ok = take == ts::PlanOptions::Take::kTaken;
    }
    if (!ok) return usage_error("plan " + method + ": " + arg + (has ? " '" + value + "'" : "") + ": takes " + form);
    ++i;
  }
  std::string error;
  bool usage = false;
  const std::shared_ptr<const ts::PlanModel> model = options->finish(error, usage);
  if (model == nullptr) return usage ? usage_error(error) : fail(error);
  // PLAN.json's place is tried before the work, not after it.
  const std::string json_tmp = json_path.empty() ? "" : json_path + ".tmp";
  if (!json_tmp.empty()) {
    const std::string cause = file_cause(json_path);
    if (!cause.empty()) return fail(json_path + ": cannot be written (" + cause + ")");
  }
  ts::Progress progress("plan " + method, "evaluations");
  const ts::PlanPrediction p =
      ts::predict_plan(*model, [&progress](std::size_t done, std::size_t total) { progress.update(done, total); });
  ts::Progress searching("plan " + method + ": changes", "plans");
  const std::vector<ts::PlanSuggestion> s = ts::suggest_changes(
      *model, p, suggest, [&searching](std::size_t done, std::size_t total) { searching.update(done, total); });
  const std::string table = ts::plan_table(*model, p, s, suggest > 0) + options->hint(p);
  std::printf("%s", table.c_str());
  if (!json_tmp.empty()) {
    if (!write_text_file(json_tmp, ts::plan_json(*model, p, s)) || std::rename(json_tmp.c_str(), json_path.c_str()) != 0) {
      const int error_number = errno;
      std::remove(json_tmp.c_str());
      return fail(cannot_write(json_path, error_number));
    }
  }
  return p.ok ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage_error("no METHOD");
  const std::string first = argv[1];
  if (first == "log") return run_log(argc, argv);
  if (first == "plan") return run_plan(argc, argv);
  if (first == "linuxcnc-kins") return run_kins_export(argc, argv, false);
  if (first == "linuxcnc-trt") return run_kins_export(argc, argv, true);
  const CalibrateMethod* method = trueaxis::sim::find_calibrate_method(first);
  // --help and --version anywhere after METHOD, or in its place.
  const int options_from = method != nullptr ? 2 : 1;
  const int options_to = method != nullptr ? argc : 2;
  for (int i = options_from; i < options_to; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      if (method != nullptr) {
        print_method_help(*method);
      } else {
        print_help();
      }
      return 0;
    }
    if (arg == "--version") {
      std::printf("%s\n", trueaxis::sim::version_line("trueaxis-calibrate").c_str());
      return 0;
    }
  }
  if (method == nullptr) {
    return usage_error("unknown METHOD '" + first + "': " + trueaxis::sim::calibrate_method_names());
  }

  CalibrateOptions o;
  o.method = method->name;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--store") {
      o.store = true;
    } else if (arg == "--check") {
      o.check = true;
    } else if (arg == "--operator" && has_value) {
      o.operator_name = argv[++i];
      if (!printable_utf8(o.operator_name)) return usage_error("--operator takes a name in UTF-8 without control characters");
    } else if (arg == "--machine-name" && has_value) {
      o.machine_name = argv[++i];
      if (o.machine_name.empty() || !printable_utf8(o.machine_name)) {
        return usage_error("--machine-name takes a name in UTF-8 without control characters");
      }
    } else if (arg == "--time" && has_value) {
      o.log_time = parse_time(argv[++i]);
      if (o.log_time == 0.0) {
        return usage_error("--time takes Unix seconds or a UTC date and time (2027-01-15T08:00:00Z)");
      }
    } else if (arg == "--in" && has_value) {
      o.in_path = argv[++i];
    } else if (arg == "--json" && has_value) {
      o.json_path = argv[++i];
    } else if (arg == "--machine" && has_value) {
      o.machine_path = argv[++i];
    } else if (arg == "--report" && has_value) {
      o.report_dir = argv[++i];
    } else if (arg == "--linuxcnc-comp" && has_value) {
      o.linuxcnc_comp_path = argv[++i];
    } else if (arg == "--linuxcnc-kins" && has_value) {
      o.linuxcnc_kins_path = argv[++i];
    } else if (arg == "--sub-machines" && has_value) {
      const std::string list = argv[++i];
      o.sub_machines.clear();
      std::size_t from = 0;
      bool ok = !list.empty();
      while (ok && from <= list.size()) {
        const std::size_t comma = std::min(list.find(',', from), list.size());
        const std::string n = list.substr(from, comma - from);
        ok = n.size() == 1 && n[0] >= '1' && n[0] <= '8' &&
             std::count(o.sub_machines.begin(), o.sub_machines.end(), n[0] - '0') == 0;
        if (ok) o.sub_machines.push_back(n[0] - '0');
        from = comma + 1;
      }
      if (!ok) return usage_error("--sub-machines takes N,N,... : sub-machines 1..8, each once");
    } else if (arg == "--accept-change") {
      o.accept_change = true;
    } else if (arg == "--unlock-code" && has_value) {
      char* end = nullptr;
      const long code = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || code < 1 || code > 9999) return usage_error("--unlock-code takes 1..9999");
      o.unlock_code = static_cast<double>(code);
    } else if (arg == "--wait" && has_value) {
      char* end = nullptr;
      const long seconds = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || seconds < 0 || seconds > 3600) return usage_error("--wait takes 0..3600 (seconds)");
      o.wait_s = static_cast<int>(seconds);
    } else if (arg == "--host" && has_value) {
      o.host = argv[++i];
    } else if (arg == "--port" && has_value) {
      char* end = nullptr;
      const long port = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || port < 1 || port > 65535) return usage_error("--port takes 1..65535");
      o.port = static_cast<int>(port);
    } else {
      return usage_error("unknown or incomplete option '" + arg + "'");
    }
  }
  if (o.in_path.empty() || o.json_path.empty()) return usage_error("--in and --json are required");
  if (o.log_time == 0.0) o.log_time = static_cast<double>(std::time(nullptr));
  if (o.accept_change && !o.store) return usage_error("--accept-change goes with --store");
  if (o.check && o.store) {
    return usage_error("--check compares with the stored calibration and stores nothing: not with --store");
  }
  if (!o.sub_machines.empty() && o.method != "gantry") {
    return usage_error("--sub-machines goes with gantry (the sub-machines a session measures)");
  }
  if (!o.linuxcnc_comp_path.empty() && o.method != "rigidity") {
    return usage_error("--linuxcnc-comp goes with rigidity (M3's A positioning error)");
  }
  if (!o.linuxcnc_comp_path.empty() && !o.store) {
    return usage_error("--linuxcnc-comp goes with --store: the joint's compensation is the stored table's A "
                       "positioning error, not a table the controller does not hold");
  }
  if (!o.linuxcnc_comp_path.empty() && !o.linuxcnc_kins_path.empty()) {
    return usage_error("--linuxcnc-comp and --linuxcnc-kins both correct the A positioning error (the kinematics' "
                       "table holds it): together they correct it twice; give one");
  }
  if (!o.linuxcnc_kins_path.empty() && (method->kins_file == nullptr || !o.store)) {
    return usage_error("--linuxcnc-kins goes with rigidity or spindle, and --store (the kinematics take the stored "
                       "calibration)");
  }

  // Every output is tried before anything is sent: a report found unwritable
  // after an hour of streaming would lose the hour. Each names its cause.
  {
    const std::string nothing = "; nothing was sent to the controller, nothing stored";
    const std::pair<const char*, const std::string*> files[] = {
        {"--json", &o.json_path}, {"--linuxcnc-comp", &o.linuxcnc_comp_path}, {"--linuxcnc-kins", &o.linuxcnc_kins_path}};
    for (const auto& [option, path] : files) {
      if (path->empty()) continue;
      for (const auto& [other, other_path] : files) {
        if (other != option && *other_path == *path) {
          return usage_error(std::string(option) + " and " + other + " name the same file '" + *path + "'");
        }
      }
      const std::string cause = file_cause(*path);
      if (!cause.empty()) return fail(*path + ": cannot be written (" + cause + ")" + nothing);
    }
    if (!o.report_dir.empty()) {
      const std::string cause = report_cause(o.report_dir);
      if (!cause.empty()) return fail(o.report_dir + ": the report cannot be made there (" + cause + ")" + nothing);
    }
  }

  trueaxis::sim::VariableClient client;
  if (!client.connect(o.host, o.port)) {
    return fail("cannot connect to " + o.host + ":" + std::to_string(o.port) + ": " + client.error_text());
  }
  const std::string busy = "controller busy: another client holds the macro interface";
  const auto waiting = [&busy, &o] {
    std::fprintf(stderr, "trueaxis-calibrate: %s, waiting (up to %d s)\n", busy.c_str(), o.wait_s);
  };
  const bool taken = client.take_interface(o.wait_s * 1000, waiting);
  if (!taken) {
    const std::string why = client.failure_text();
    if (why == busy) return fail(busy + " (waited " + std::to_string(o.wait_s) + " s; --wait SECONDS)");
    return fail(why + (client.exception() == 0 ? " while taking the controller's macro interface (#9009); nothing "
                                                 "was sent, nothing stored"
                                               : ""));
  }
  // Contract 5 of calibrate.hpp: a transport failure says what was under way,
  // and what became of the store.
  const std::string nothing_stored = "; nothing was stored";
  const auto failed = [&nothing_stored](const FlowResult& f) {
    return fail(f.error + (f.transport_failed ? nothing_stored : ""));
  };
  FlowResult r = method->calibrate(client, o);
  if (!r.ok) return failed(r);
  r.log_time = o.log_time;
  trueaxis::macros::Verdict verdict = trueaxis::macros::Verdict::kPass;
  if (o.check && !trueaxis::sim::check_built(client, *method, r, verdict)) return failed(r);
  if (o.check && !o.report_dir.empty()) {
    // The report shows this method's drift, the check just logged included.
    // A module that cannot give its log (older firmware) leaves the drift out:
    // the check itself stands.
    // check_built read the log, the check's entry included.
    if (r.log_read) {
      std::vector<trueaxis::sim::Drift> drift;
      for (const trueaxis::sim::Drift& d : trueaxis::sim::fit_drift(r.log_rows)) {
        if (d.method == method->name) drift.push_back(d);
      }
      r.report_extras = trueaxis::sim::with_member(r.report_extras, "\"drift\": " + trueaxis::sim::drift_json(drift));
    } else {
      std::fprintf(stderr, "trueaxis-calibrate: the report shows no drift: the module's log could not be read\n");
    }
  }
  // For the record only: a module without #902 (older firmware) reads as not set.
  double machine_id = 0.0;
  double interface_version = 0.0;
  if (!client.read_one(trueaxis::macros::var::kMachineId, machine_id)) machine_id = 0.0;
  if (!client.read_one(trueaxis::macros::var::kInterfaceVersion, interface_version)) interface_version = 0.0;
  r.report_extras = with_record(r.report_extras, o, o.check ? trueaxis::macros::verdict_name(verdict) : "",
                                machine_id, interface_version);
  if (!r.as_given.empty()) {  // the MACHINE values no data tested, for the report's record
    std::string list;
    for (const std::string& given : r.as_given) list += (list.empty() ? "" : ", ") + trueaxis::sim::json_string(given);
    r.report_extras = trueaxis::sim::with_member(r.report_extras, "\"taken_as_given\": [" + list + "]");
  }
  // The kinematics' file: the table or model just built (R = 0, 9837 or 9847);
  // the store builds the same session again, deterministically, so it is the
  // one stored.
  std::string kins_file;
  r.stage = "exporting the LinuxCNC kinematics' file (" + o.linuxcnc_kins_path + ")";
  if (!o.linuxcnc_kins_path.empty() && !method->kins_file(client, false, kins_file, r)) {
    return failed(r);
  }
  // The macros this run has counted: the store checks that no other client ran
  // one since (the interface is free once #903 s pass without a write, and the
  // report is made meanwhile), so that what it stores is built from this run's session.
  double done_count = 0.0;
  if (!client.read_one(trueaxis::macros::var::kDoneCount, done_count)) {
    return fail(client.failure_text() + " while reading the controller's macro count (#9003)" + nothing_stored);
  }

  // OUT.json and the report go to temporaries beside their targets first and
  // into place last, after the store: on any failure neither is there and
  // nothing is stored.
  const std::string tmp = o.json_path + ".tmp";
  const std::string comp_tmp = o.linuxcnc_comp_path.empty() ? "" : o.linuxcnc_comp_path + ".tmp";
  const std::string kins_tmp = o.linuxcnc_kins_path.empty() ? "" : o.linuxcnc_kins_path + ".tmp";
  std::string report_tmp;
  const auto fail_clean = [&tmp, &comp_tmp, &kins_tmp, &report_tmp](const std::string& line) {
    std::remove(tmp.c_str());
    if (!comp_tmp.empty()) std::remove(comp_tmp.c_str());
    if (!kins_tmp.empty()) std::remove(kins_tmp.c_str());
    remove_tree(report_tmp);
    return fail(line);
  };
  if (!write_text_file(tmp, r.json)) return fail_clean(cannot_write(o.json_path, errno));
  if (!comp_tmp.empty() && !write_text_file(comp_tmp, r.linuxcnc_comp)) {
    return fail_clean(cannot_write(o.linuxcnc_comp_path, errno));
  }
  if (!kins_tmp.empty() && !write_text_file(kins_tmp, kins_file)) {
    return fail_clean(cannot_write(o.linuxcnc_kins_path, errno));
  }
  std::string summary = r.summary + "; wrote " + o.json_path;
  if (!comp_tmp.empty()) summary += ", " + o.linuxcnc_comp_path;
  if (!kins_tmp.empty()) summary += ", " + o.linuxcnc_kins_path;
  if (!o.report_dir.empty()) {
    std::string dir = o.report_dir;
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    std::string templ = dir + ".tmp-XXXXXX";
    struct stat st {};
    const bool usable = ::stat(dir.c_str(), &st) != 0 ? errno == ENOENT : S_ISDIR(st.st_mode);
    if (usable && ::mkdtemp(templ.data()) != nullptr) report_tmp = templ;
    if (report_tmp.empty()) {
      const std::string cause = report_cause(dir);
      return fail_clean(o.report_dir + ": the report cannot be made there (" +
                        (cause.empty() ? std::string(std::strerror(errno)) : cause) + ")");
    }
    if (!write_text_file(report_tmp + "/module_figures.json", r.report_extras) ||
        !write_map(report_tmp + "/register_map.json") || !make_report(*method, report_tmp, tmp)) {
      return fail_clean(o.report_dir + ": the report could not be made (" TRUEAXIS_PYTHON " " TRUEAXIS_REPORT_SCRIPT ")");
    }
    summary += ", report " + o.report_dir + "/index.html";
  }
  r.unlock_code = o.unlock_code;
  r.accept_change = o.accept_change;
  if (o.store) {
    double done_now = -1.0;
    if (!client.take_interface(o.wait_s * 1000, waiting) || !client.read_one(trueaxis::macros::var::kDoneCount, done_now)) {
      return fail_clean(client.failure_text() + " while taking the macro interface again for the store" + nothing_stored);
    }
    if (done_now != done_count) {
      return fail_clean("another client ran macros on the controller while the report was made (the macro interface "
                        "is free after #903 s without a write, default 30): nothing stored; run the command again");
    }
  }
  // The table is stored once the store's macro succeeded: a failure after it says so.
  const trueaxis::macros::RecordSpec* record = trueaxis::sim::stored_record(method->name);
  const std::string was_stored =
      !o.store ? ""
               : "; the table WAS stored" +
                     (record != nullptr ? " (record " + std::to_string(record->key) + " " + record->name + ")"
                                        : std::string()) +
                     ": `trueaxis-calibrate log` shows the store";
  bool had_table = true;
  if (o.store && !trueaxis::sim::has_stored_table(client, *method, had_table, r)) {
    return fail_clean(r.error + nothing_stored);
  }
  if (o.store && !method->store(client, r)) {
    if (r.stored) return fail_clean(r.error + was_stored + "; OUT.json and the report were not written");
    if (r.transport_failed && r.macro_started) {
      return fail_clean(r.error + "; whether the table was stored is not known (the connection failed after the store's "
                                  "macro was sent): `trueaxis-calibrate log` shows it");
    }
    return fail_clean(r.error + (r.transport_failed ? nothing_stored : ""));
  }
  summary += o.store ? "; " + stored_text(method->name) + (had_table ? "" : ", the first this controller stores") : "; not stored";
  if (!r.as_given_summary.empty()) summary += "; taken as given (no data tests them): " + r.as_given_summary;
  client.give_back_interface();  // closing gives it back too; this is at once
  client.close();
  if (!report_tmp.empty() && !place_report(report_tmp, o.report_dir)) {
    report_tmp.clear();  // place_report removed it
    return fail_clean(o.report_dir + ": the report could not be moved into place" + was_stored);
  }
  report_tmp.clear();
  if (!comp_tmp.empty() && std::rename(comp_tmp.c_str(), o.linuxcnc_comp_path.c_str()) != 0) {
    return fail_clean(cannot_write(o.linuxcnc_comp_path, errno) + was_stored);
  }
  if (!kins_tmp.empty() && std::rename(kins_tmp.c_str(), o.linuxcnc_kins_path.c_str()) != 0) {
    return fail_clean(cannot_write(o.linuxcnc_kins_path, errno) + was_stored);
  }
  if (std::rename(tmp.c_str(), o.json_path.c_str()) != 0) {
    return fail_clean(cannot_write(o.json_path, errno) + was_stored);
  }
  std::printf("%s\n", summary.c_str());
  return o.check && verdict == trueaxis::macros::Verdict::kFail ? 3 : 0;
}
