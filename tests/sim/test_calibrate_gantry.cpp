// `trueaxis-calibrate gantry` (INTERFACE.md "The integrator's command", "M2
// gantry"): its flow (calibrate_gantry, store_gantry) driven in this process
// against a simulator served in this process too (a thread, 127.0.0.1 port 0, RAM
// storage), on files the virtual laser tracker measured off the virtual gantry
// (gantry_measure.hpp), with that gantry's truth beside them:
//  1. good data: OUT.json parses, every origin within 3 sigma of the truth,
//     global_T_sub a rigid transform; the stored frames convert (9825) as
//     OUT.json's global_T_sub says; any CSV order gives the same OUT.json; a
//     later session of one sub-machine replaces only that one;
//  2. every bad input gets its own one-line error (the file and physical line, or
//     the module's code) and stores nothing: 9825 answers afterwards exactly as
//     before (no_table, or the frames stored earlier), and the module is locked;
//  3. the command itself (its binary, against the same simulator) with --store
//     and --report: the page and its figures from simulator data.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include <dirent.h>
#include <fcntl.h>
#include <ftw.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "trueaxis/core/status.hpp"
#include "trueaxis/hal/posix/steady_clock.hpp"
#include "trueaxis/hal/ram_nv_storage.hpp"
#include "trueaxis/macros/gantry/gantry_map.hpp"
#include "trueaxis/macros/module.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/sim/calibrate.hpp"
#include "trueaxis/sim/gantry_measure.hpp"
#include "trueaxis/sim/modbus_server.hpp"
#include "trueaxis/sim/request_handler.hpp"
#include "trueaxis/sim/simulator.hpp"
#include "trueaxis/sim/variable_router.hpp"

extern char** environ;

namespace {

namespace v = trueaxis::macros::var;
namespace sim = trueaxis::sim;
using trueaxis::core::Status;

// ---- the simulator, in this process ---------------------------------------------------

volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_wake(int) {}

// trueaxis-sim's parts (sim_main.cpp) on RAM storage, served by a thread until
// the destructor: it sets the stop flag and wakes the thread's ppoll with
// SIGUSR1 (blocked in that thread but while it waits, so it cannot be lost).
class InProcessSim {
 public:
  InProcessSim()
      : nv_(trueaxis::macros::kRequiredStorageBytes),
        storage_(nv_.data(), nv_.size()),
        module_(std::make_unique<trueaxis::macros::Module>(storage_, clock_)) {
    REQUIRE(module_->start() == Status::kOk);
    simulator_ = std::make_unique<sim::Simulator>(*module_, sim::FaceConfig{}, 1);
    router_ = std::make_unique<sim::VariableRouter>(*module_, *simulator_);
    handler_ = std::make_unique<sim::RequestHandler>(*router_);
    server_ = std::make_unique<sim::ModbusTcpServer>(*handler_, *simulator_);
    REQUIRE(server_->listen("127.0.0.1", 0));
    struct sigaction wake {};
    wake.sa_handler = on_wake;
    sigemptyset(&wake.sa_mask);
    sigaction(SIGUSR1, &wake, nullptr);
    std::signal(SIGPIPE, SIG_IGN);
    g_stop = 0;
    thread_ = std::thread([this] {
      sigset_t usr1, wait_mask;
      sigemptyset(&usr1);
      sigaddset(&usr1, SIGUSR1);
      pthread_sigmask(SIG_BLOCK, &usr1, &wait_mask);
      sigdelset(&wait_mask, SIGUSR1);
      server_->serve(g_stop, wait_mask);
    });
    REQUIRE(client_.connect("127.0.0.1", server_->port()));
  }
  ~InProcessSim() {
    client_.close();
    g_stop = 1;
    pthread_kill(thread_.native_handle(), SIGUSR1);
    thread_.join();
  }
  InProcessSim(const InProcessSim&) = delete;
  InProcessSim& operator=(const InProcessSim&) = delete;

  int port() const { return server_->port(); }
  sim::VariableClient& client() { return client_; }

 private:
  std::vector<std::uint8_t> nv_;
  trueaxis::hal::RamNvStorage storage_;
  trueaxis::hal::SteadyClock clock_;
  std::unique_ptr<trueaxis::macros::Module> module_;
  std::unique_ptr<sim::Simulator> simulator_;
  std::unique_ptr<sim::VariableRouter> router_;
  std::unique_ptr<sim::RequestHandler> handler_;
  std::unique_ptr<sim::ModbusTcpServer> server_;
  std::thread thread_;
  sim::VariableClient client_;
};

// ---- files ------------------------------------------------------------------------------

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool exists(const std::string& path) { return ::access(path.c_str(), F_OK) == 0; }

int remove_entry(const char* path, const struct stat*, int, struct FTW*) { return std::remove(path); }

struct Workspace {
  std::string dir;
  Workspace() {
    char path[] = "/tmp/trueaxis-calibrate-gantry-XXXXXX";
    REQUIRE(::mkdtemp(path) != nullptr);
    dir = path;
  }
  ~Workspace() { ::nftw(dir.c_str(), remove_entry, 16, FTW_DEPTH | FTW_PHYS); }
  std::string file(const std::string& name) const { return dir + "/" + name; }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name), std::ios::binary | std::ios::trunc) << text;
    return file(name);
  }
};

// The virtual gantry measured by the virtual tracker: the three files' texts.
struct Measured {
  std::string samples, machine, truth;
};

Measured measure(const sim::GantryPlan& plan, std::uint64_t seed) {
  const sim::GantryMachine machine(sim::realistic_gantry());
  const sim::LaserTracker tracker = sim::place_tracker(machine, sim::TrackerPlacement{});
  sim::SimRng rng(seed);
  return {sim::samples_csv_text(sim::measure_gantry(machine, tracker, plan, rng), {"measured"}),
          sim::machine_csv_text(machine, tracker), sim::truth_json_text(machine, tracker, plan)};
}

// A plan of fewer points: the bad inputs need a whole stream, not its precision.
sim::GantryPlan small_plan() {
  sim::GantryPlan p;
  p.pad_grid = 3;
  p.side_rows = 3;
  p.side_cols = 3;
  p.passes = 2;
  p.pass_points = 8;
  p.circle_points = 12;
  return p;
}

// A samples file as its data rows (group, the whole line); comments and the header dropped.
struct Row {
  std::string group, text;
};
const std::string kHeader = "group,x_mm,y_mm,z_mm\n";

std::vector<Row> rows_of(const std::string& csv) {
  std::vector<Row> rows;
  std::istringstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("group,", 0) == 0) continue;
    rows.push_back({line.substr(0, line.find(',')), line});
  }
  return rows;
}

std::string text_of(const std::vector<Row>& rows) {
  std::string out = kHeader;
  for (const Row& r : rows) out += r.text + "\n";
  return out;
}

// ---- a small strict JSON reader -------------------------------------------------------------

struct Json {
  enum Kind { kNull, kNumber, kString, kArray, kObject } kind = kNull;
  double number = 0.0;
  std::string text;
  std::vector<Json> items;
  std::vector<std::pair<std::string, Json>> members;
  const Json& operator[](const std::string& key) const {
    static const Json missing;
    for (const auto& kv : members) {
      if (kv.first == key) return kv.second;
    }
    return missing;
  }
  std::vector<double> numbers() const {
    std::vector<double> out;
    for (const Json& j : items) out.push_back(j.kind == kNumber ? j.number : std::nan(""));
    return out;
  }
};

class JsonReader {
 public:
  explicit JsonReader(const std::string& s) : s_(s) {}
  bool parse(Json& out) {
    const bool ok = value(out);
    space();
    return ok && at_ == s_.size();
  }

 private:
  void space() {
    while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) ++at_;
  }
  bool eat(char c) {
    space();
    if (at_ >= s_.size() || s_[at_] != c) return false;
    ++at_;
    return true;
  }
  bool string(std::string& out) {
    if (!eat('"')) return false;
    while (at_ < s_.size() && s_[at_] != '"') out += s_[at_++];
    return eat('"');
  }
  bool value(Json& out) {
    space();
    if (at_ >= s_.size()) return false;
    if (s_[at_] == '{') {
      out.kind = Json::kObject;
      ++at_;
      if (eat('}')) return true;
      do {
        std::pair<std::string, Json> kv;
        if (!string(kv.first) || !eat(':') || !value(kv.second)) return false;
        out.members.push_back(std::move(kv));
      } while (eat(','));
      return eat('}');
    }
    if (s_[at_] == '[') {
      out.kind = Json::kArray;
      ++at_;
      if (eat(']')) return true;
      do {
        out.items.emplace_back();
        if (!value(out.items.back())) return false;
      } while (eat(','));
      return eat(']');
    }
    if (s_[at_] == '"') {
      out.kind = Json::kString;
      return string(out.text);
    }
    if (s_.compare(at_, 4, "true") == 0) {
      at_ += 4;
      return true;
    }
    const std::size_t end = s_.find_first_not_of("+-0123456789.eE", at_);
    const std::string token = s_.substr(at_, end - at_);
    char* stop = nullptr;
    out.number = std::strtod(token.c_str(), &stop);
    if (token.empty() || *stop != '\0') return false;
    out.kind = Json::kNumber;
    at_ = end;
    return true;
  }
  const std::string& s_;
  std::size_t at_ = 0;
};

Json parse(const std::string& text) {
  Json j;
  INFO(text);
  REQUIRE(JsonReader(text).parse(j));
  return j;
}

const Json& sub_of(const Json& doc, int id) {
  for (const Json& s : doc["sub_machines"].items) {
    if (s["id"].number == id) return s;
  }
  FAIL("no sub-machine " << id);
  return doc;
}

double distance(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < 3; ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(sum);
}

// A global point into sub-machine coordinates through global_T_sub (row-major).
std::vector<double> to_sub(const std::vector<double>& t, const std::vector<double>& p) {
  std::vector<double> q(3, 0.0);
  for (std::size_t j = 0; j < 3; ++j) {
    for (std::size_t i = 0; i < 3; ++i) q[j] += t[4 * i + j] * (p[i] - t[4 * i + 3]);
  }
  return q;
}

// ---- the module ------------------------------------------------------------------------------

const std::vector<double> kPoint = {400.0, 1100.0, 150.0};  // a workpiece point, global frame

// 9825 for sub-machines 1..4 at kPoint: each #100..#102 or {error code}.
std::vector<std::vector<double>> conversions(sim::VariableClient& client) {
  std::vector<std::vector<double>> out;
  for (int n = 1; n <= 4; ++n) {
    REQUIRE(client.write_one(v::kArgT, n));
    REQUIRE(client.write(v::kArgX, 3, kPoint.data()));
    const sim::MacroOutcome o = client.run_macro(9825);
    REQUIRE(o.status >= 2);
    if (o.status == 3) {
      out.push_back({static_cast<double>(o.error)});
      continue;
    }
    std::vector<double> p(3);
    REQUIRE(client.read(v::kGantryPointX, 3, p.data()));
    out.push_back(p);
  }
  return out;
}

double read_var(sim::VariableClient& client, std::uint16_t number) {
  double x = 0.0;
  REQUIRE(client.read_one(number, x));
  return x;
}

std::string module_error(Status s) {
  return "module error " + std::to_string(static_cast<int>(s)) + " " + trueaxis::core::status_name(s) + ": " +
         trueaxis::core::status_message(s);
}

// The command's flow as calibrate_main.cpp runs it, without the files: the
// flow, then (on success, with store) the store.
sim::FlowResult flow(sim::VariableClient& client, const std::string& in, const std::string& machine, bool store) {
  sim::CalibrateOptions o;
  o.method = "gantry";
  o.in_path = in;
  o.machine_path = machine;
  o.json_path = "unused.json";
  o.store = store;
  sim::FlowResult r = sim::calibrate_gantry(client, o);
  if (r.ok && store) {
    sim::FlowResult s;
    if (!sim::store_gantry(client, s)) return s;
  }
  return r;
}

// The command's binary, argv without a shell: its exit code and stderr.
std::pair<int, std::string> run_command(const std::vector<std::string>& argv, const std::string& err_path) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(rc == 0);
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), slurp(err_path)};
}

}  // namespace

TEST_CASE("calibrate gantry: the frames of the virtual gantry, within 3 sigma of its truth, stored and converting",
          "[calibrate][gantry]") {
  InProcessSim sim;
  sim::VariableClient& client = sim.client();
  Workspace w;
  const Measured m = measure(sim::GantryPlan{}, 1);
  const std::string samples = w.write("samples.csv", m.samples);
  const std::string machine = w.write("machine.csv", m.machine);
  const Json truth = parse(m.truth);
  for (const auto& c : conversions(client)) CHECK(c == std::vector<double>{404.0});  // no_table

  const sim::FlowResult r = flow(client, samples, machine, true);
  INFO(r.error);
  REQUIRE(r.ok);
  CHECK(read_var(client, v::kUnlock) == 0.0);  // locked again
  const Json out = parse(r.json);
  CHECK(out["method"].text == "gantry");
  for (const char* key : {"origin_mm", "x", "y", "z"}) CHECK(out["global"][key].numbers().size() == 3);
  CHECK(out["global"]["bed_flatness_mm"].kind == Json::kNumber);
  CHECK(out["global"]["gantry_straightness_mm"].kind == Json::kNumber);
  REQUIRE(out["sub_machines"].items.size() == 4);
  const std::vector<std::vector<double>> converted = conversions(client);
  for (int n = 1; n <= 4; ++n) {
    CAPTURE(n);
    const Json& s = sub_of(out, n);
    const Json& t = sub_of(truth, n);
    CHECK(s["master_axis"].text == t["master_axis"].text);
    for (const char* pair : {"xy", "yz", "zx"}) CHECK(s["squareness_arcsec"][pair].kind == Json::kNumber);
    CHECK(s["a_c_offset_mm"].kind == Json::kNumber);
    CHECK(s["a_c_angle_deg"].number == Approx(90.0).margin(0.1));
    // The origin within 3 sigma of the truth (the sigma from the data's scatter).
    const double sigma = s["origin_sigma_mm"].number;
    CHECK(sigma > 0.001);
    CHECK(sigma < 0.1);
    const double error = distance(s["origin_mm"].numbers(), t["origin_mm"].numbers());
    CAPTURE(error, sigma);
    CHECK(error < 3.0 * sigma);
    // global_T_sub: [x' y' z' O] as columns, rows 1-3 orthonormal, last row 0 0 0 1.
    const std::vector<double> T = s["global_T_sub"].numbers();
    REQUIRE(T.size() == 16);
    CHECK(std::vector<double>(T.begin() + 12, T.end()) == std::vector<double>{0, 0, 0, 1});
    const std::vector<double> cols[3] = {s["x"].numbers(), s["y"].numbers(), s["z"].numbers()};
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(T[4 * i + 3] == s["origin_mm"].numbers()[i]);
      for (std::size_t j = 0; j < 3; ++j) {
        CHECK(T[4 * i + j] == cols[j][i]);
        double dot = 0.0;
        for (std::size_t k = 0; k < 3; ++k) dot += T[4 * k + i] * T[4 * k + j];
        CHECK(dot == Approx(i == j ? 1.0 : 0.0).margin(1e-12));
      }
    }
    const double det = T[0] * (T[5] * T[10] - T[6] * T[9]) - T[1] * (T[4] * T[10] - T[6] * T[8]) +
                       T[2] * (T[4] * T[9] - T[5] * T[8]);
    CHECK(det == Approx(1.0).margin(1e-12));
    // What the controller stored converts as OUT.json says.
    const std::vector<double> q = to_sub(T, kPoint);
    REQUIRE(converted[static_cast<std::size_t>(n - 1)].size() == 3);
    CHECK(distance(converted[static_cast<std::size_t>(n - 1)], q) < 1e-9);
  }
  // The report's extra figures are not OUT.json's.
  CHECK(r.json.find("\"straightness_mm\"") == std::string::npos);
  CHECK(r.report_extras.find("sub_machine_figures") != std::string::npos);

  SECTION("any CSV order: groups interleaved, each group's own order kept, gives the same OUT.json") {
    std::vector<Row> rows = rows_of(m.samples);
    std::vector<Row> mixed;
    // Round robin over the groups, last group first.
    std::vector<std::string> groups;
    for (const Row& row : rows) {
      if (std::find(groups.begin(), groups.end(), row.group) == groups.end()) groups.push_back(row.group);
    }
    std::reverse(groups.begin(), groups.end());
    std::vector<std::size_t> next(groups.size(), 0);
    for (bool any = true; any;) {
      any = false;
      for (std::size_t g = 0; g < groups.size(); ++g) {
        std::size_t seen = 0;
        for (const Row& row : rows) {
          if (row.group != groups[g]) continue;
          if (seen++ == next[g]) {
            mixed.push_back(row);
            ++next[g];
            any = true;
            break;
          }
        }
      }
    }
    REQUIRE(mixed.size() == rows.size());
    REQUIRE(mixed.front().group != rows.front().group);
    const sim::FlowResult again = flow(client, w.write("mixed.csv", "# mixed\n" + text_of(mixed)), machine, false);
    INFO(again.error);
    REQUIRE(again.ok);
    CHECK(again.json == r.json);
  }
  SECTION("a session of one sub-machine, with the whole MACHINE file, replaces that one only") {
    std::vector<Row> rows = rows_of(measure(small_plan(), 7).samples);
    rows.erase(std::remove_if(rows.begin(), rows.end(),
                              [](const Row& row) { return row.group.rfind("sp", 0) == 0 && row.group.rfind("sp2_", 0) != 0; }),
               rows.end());
    const sim::FlowResult two = flow(client, w.write("sp2.csv", text_of(rows)), machine, true);
    INFO(two.error);
    REQUIRE(two.ok);
    REQUIRE(parse(two.json)["sub_machines"].items.size() == 1);
    const std::vector<std::vector<double>> now = conversions(client);
    CHECK(now[0] == converted[0]);
    CHECK(now[1] != converted[1]);
    CHECK(now[2] == converted[2]);
    CHECK(now[3] == converted[3]);
    CHECK(distance(now[1], to_sub(sub_of(parse(two.json), 2)["global_T_sub"].numbers(), kPoint)) < 1e-9);
  }
}

TEST_CASE("calibrate gantry: every bad input has its own error and stores nothing", "[calibrate][gantry]") {
  InProcessSim sim;
  sim::VariableClient& client = sim.client();
  Workspace w;
  const Measured m = measure(small_plan(), 3);
  const std::vector<Row> good = rows_of(m.samples);
  const std::string machine = w.write("machine.csv", m.machine);
  const std::string bad = w.file("bad.csv");

  struct Case {
    std::string name, samples, machine, error;  // error: the whole line, or its start
    bool whole;
  };
  std::vector<Case> cases;
  // Lines 1 comment, 2 header, then good[k] on line 3 + k.
  const auto with = [&](const std::vector<Row>& rows) { return "# bad\n" + text_of(rows); };
  const auto line_of = [](std::size_t k) { return std::to_string(3 + k); };
  const auto replaced = [&](std::size_t k, const std::string& text) {
    std::vector<Row> rows = good;
    rows[k].text = text;
    return with(rows);
  };
  const auto without = [&](const std::string& group) {
    std::vector<Row> rows;
    for (const Row& r : good) {
      if (r.group != group) rows.push_back(r);
    }
    return with(rows);
  };
  const auto at = [&](std::size_t k, const std::string& what) { return bad + ":" + line_of(k) + ": " + what; };

  std::size_t first_sp1_x = 0;
  while (good[first_sp1_x].group != "sp1_x_1") ++first_sp1_x;
  cases.push_back({"a malformed row", replaced(40, "side_1,1.5,abc,3"), machine,
                   at(40, "'y_mm' is not a finite number: 'abc'"), true});
  cases.push_back({"a missing field", replaced(41, "side_1,1.5,2"), machine,
                   at(41, "too few fields: no value for 'z_mm'"), true});
  cases.push_back({"nan", replaced(first_sp1_x + 2, "sp1_x_1,1,2,nan"), machine,
                   at(first_sp1_x + 2, "'z_mm' is not a finite number: 'nan'"), true});
  cases.push_back({"inf", replaced(5, "bed,inf,2,3"), machine, at(5, "'x_mm' is not a finite number: 'inf'"), true});
  cases.push_back({"an unknown group", replaced(first_sp1_x, "sp1_w_1,1,2,3"), machine,
                   at(first_sp1_x, "unknown group 'sp1_w_1'"), true});
  cases.push_back({"a misspelt group", replaced(3, "beds,1,2,3"), machine, at(3, "unknown group 'beds'"), true});
  cases.push_back({"sub-machine 9", replaced(first_sp1_x, "sp9_x_1,1,2,3"), machine,
                   at(first_sp1_x, "group 'sp9_x_1': the sub-machine N must be 1..8"), true});
  cases.push_back({"sub-machine 0", replaced(first_sp1_x, "sp0_c,1,2,3"), machine,
                   at(first_sp1_x, "group 'sp0_c': the sub-machine N must be 1..8"), true});
  cases.push_back({"a leading zero", replaced(first_sp1_x, "sp01_c,1,2,3"), machine,
                   at(first_sp1_x, "group 'sp01_c': the sub-machine N must be 1..8"), true});
  cases.push_back({"pass 5", replaced(first_sp1_x, "sp1_x_5,1,2,3"), machine,
                   at(first_sp1_x, "group 'sp1_x_5': the pass K must be 1..4"), true});
  cases.push_back({"gantry pass 0", replaced(2, "gantry_0,1,2,3"), machine,
                   at(2, "group 'gantry_0': the pass K must be 1..4"), true});
  cases.push_back({"a missing group", without("sp2_a"), machine, module_error(Status::kMissingGroup), false});
  cases.push_back({"no bed", without("bed"), machine, module_error(Status::kMissingGroup), false});
  {
    // sp3's C circle 31 points (its capacity 30): the 31st in file order is refused.
    std::vector<Row> rows = good;
    std::vector<Row> c;
    for (const Row& r : good) {
      if (r.group == "sp3_c") c.push_back(r);
    }
    REQUIRE(c.size() == 12);
    const std::size_t extra = trueaxis::macros::gantry::kMaxCirclePoints + 1 - c.size();
    for (std::size_t k = 0; k < extra; ++k) rows.push_back(c[k % c.size()]);
    cases.push_back({"a circle over its capacity", with(rows), machine,
                     bad + ":" + line_of(rows.size() - 1) + ": " + module_error(Status::kTooManyPoints), false});
    // A pass of 65 points (capacity 64).
    rows = good;
    std::size_t in_pass = 0;
    for (const Row& r : good) in_pass += r.group == "gantry_2" ? 1u : 0u;
    for (std::size_t k = in_pass; k <= trueaxis::macros::gantry::kMaxPassPoints; ++k) rows.push_back({"gantry_2", "gantry_2,1,2,3"});
    cases.push_back({"a pass over its capacity", with(rows), machine,
                     bad + ":" + line_of(rows.size() - 1) + ": " + module_error(Status::kTooManyPoints), false});
  }
  {
    // sp1's C circle measured over 20 deg only (the minimum arc is 30 deg).
    sim::GantryPlan short_arc = small_plan();
    short_arc.c_to_deg = 20.0;
    short_arc.circle_points = 5;
    std::vector<Row> rows;
    for (const Row& r : good) {
      if (r.group != "sp1_c") rows.push_back(r);
    }
    for (const Row& r : rows_of(measure(short_arc, 4).samples)) {
      if (r.group == "sp1_c") rows.push_back(r);
    }
    cases.push_back({"a C circle over 20 deg", with(rows), machine, module_error(Status::kArcTooShort), false});
  }
  {
    // sp2's A circle replaced by its C circle: A parallel to C.
    std::vector<Row> rows;
    for (const Row& r : good) {
      if (r.group != "sp2_a") rows.push_back(r);
    }
    for (const Row& r : good) {
      if (r.group == "sp2_c") rows.push_back({"sp2_a", "sp2_a" + r.text.substr(r.text.find(','))});
    }
    cases.push_back({"A parallel to C", with(rows), machine, module_error(Status::kAxesParallel), false});
  }
  {
    // sp4's x passes measured backwards: all of them, or one of two.
    const auto reversed = [&](const std::vector<std::string>& groups) {
      std::vector<Row> rows = good;
      for (const std::string& g : groups) {
        std::vector<std::size_t> at_rows;
        for (std::size_t k = 0; k < rows.size(); ++k) {
          if (rows[k].group == g) at_rows.push_back(k);
        }
        REQUIRE(at_rows.size() == 8);
        for (std::size_t k = 0; k < at_rows.size() / 2; ++k) {
          std::swap(rows[at_rows[k]], rows[at_rows[at_rows.size() - 1 - k]]);
        }
      }
      return with(rows);
    };
    cases.push_back({"every x pass backwards", reversed({"sp4_x_1", "sp4_x_2"}), machine,
                     module_error(Status::kAxisOppositeGantry), false});
    cases.push_back({"one x pass backwards", reversed({"sp4_x_2"}), machine, module_error(Status::kPassesDisagree),
                     false});
  }
  {
    // MACHINE without sub-machine 3's row (line 5: a comment, the header, then 1, 2, 3, 4).
    std::istringstream in(m.machine);
    std::string text, line;
    int number = 0;
    while (std::getline(in, line)) {
      if (++number != 5) text += line + "\n";
    }
    REQUIRE(m.machine.find("\n3,") != std::string::npos);
    REQUIRE(text.find("\n3,") == std::string::npos);
    const std::string no3 = w.write("no3.csv", text);
    cases.push_back({"a sub-machine without a MACHINE row", with(good), no3,
                     no3 + ": no row for sub-machine 3, which " + bad + " measures", true});
    const std::string twice = w.write("twice.csv", m.machine + "2,250,0,0,1\n");
    cases.push_back({"a sub-machine twice in MACHINE", with(good), twice,
                     twice + ":7: sub-machine 2 is given twice", true});
    const std::string nine = w.write("nine.csv", m.machine + "9,250,0,0,1\n");
    cases.push_back({"sub-machine 9 in MACHINE", with(good), nine, nine + ":7: sub_machine must be 1..8", true});
    const std::string word = w.write("word.csv", m.machine + "4,abc,0,0,1\n");
    cases.push_back({"a malformed MACHINE row", with(good), word,
                     word + ":7: 'swing_mm' is not a finite number: 'abc'", true});
    const std::string zero = w.write("zero.csv", m.machine.substr(0, m.machine.find("\n1,") + 1) + "1,300,0,0,0\n" +
                                                     m.machine.substr(m.machine.find("\n2,") + 1));
    cases.push_back({"a zero tool direction", with(good), zero,
                     zero + ":3: " + module_error(Status::kArgumentOutOfRange), false});
    cases.push_back({"no MACHINE file", with(good), "", "gantry needs --machine MACHINE.csv", false});
  }

  const auto check_refusals = [&](const std::vector<std::vector<double>>& before) {
    for (const Case& c : cases) {
      CAPTURE(c.name);
      w.write("bad.csv", c.samples);
      const sim::FlowResult r = flow(client, bad, c.machine, true);
      CAPTURE(r.error);
      CHECK_FALSE(r.ok);
      CHECK(r.json.empty());
      if (c.whole) {
        CHECK(r.error == c.error);
      } else {
        CHECK(r.error.compare(0, c.error.size(), c.error) == 0);
      }
      CHECK(r.error.find('\n') == std::string::npos);  // one line
      CHECK(read_var(client, v::kUnlock) == 0.0);     // locked
      CHECK(conversions(client) == before);           // nothing stored
    }
  };

  SECTION("with no frames stored: still none") {
    const std::vector<std::vector<double>> none = conversions(client);
    for (const auto& c : none) REQUIRE(c == std::vector<double>{404.0});
    check_refusals(none);
  }
  SECTION("with frames stored: they convert exactly as before") {
    const sim::FlowResult r = flow(client, w.write("good.csv", m.samples), machine, true);
    INFO(r.error);
    REQUIRE(r.ok);
    const std::vector<std::vector<double>> stored = conversions(client);
    for (const auto& c : stored) REQUIRE(c.size() == 3);
    check_refusals(stored);
  }
}

TEST_CASE("calibrate gantry: the command with --store and --report, the page drawn from simulator data",
          "[calibrate][gantry]") {
  InProcessSim sim;
  Workspace w;
  const Measured m = measure(small_plan(), 5);
  const std::string samples = w.write("samples.csv", m.samples);
  const std::string machine = w.write("machine.csv", m.machine);
  const auto command = [&](const std::string& in, const std::string& json, const std::vector<std::string>& more) {
    std::vector<std::string> argv = {TRUEAXIS_CALIBRATE_BINARY, "gantry", "--in", in, "--json", json,
                                     "--port", std::to_string(sim.port())};
    argv.insert(argv.end(), more.begin(), more.end());
    return run_command(argv, w.file("err.txt"));
  };

  // Refused: exit 1, one line, no OUT.json, no report, nothing stored.
  auto [code, err] = command(samples, w.file("out.json"), {"--store", "--report", w.file("report")});
  CHECK(code == 1);
  CHECK(err == "trueaxis-calibrate: gantry needs --machine MACHINE.csv (sub_machine,swing_mm,tool_x,tool_y,tool_z)\n");
  w.write("bad.csv", "group,x_mm,y_mm,z_mm\nbed,1,2,3\nsp1_q,1,2,3\n");
  std::tie(code, err) = command(w.file("bad.csv"), w.file("out.json"),
                                {"--machine", machine, "--store", "--report", w.file("report")});
  CHECK(code == 1);
  CHECK(err == "trueaxis-calibrate: " + w.file("bad.csv") + ":3: unknown group 'sp1_q'\n");
  CHECK_FALSE(exists(w.file("out.json")));
  CHECK_FALSE(exists(w.file("report")));
  for (const auto& c : conversions(sim.client())) CHECK(c == std::vector<double>{404.0});

  std::tie(code, err) = command(samples, w.file("out.json"),
                                {"--machine", machine, "--store", "--report", w.file("report")});
  INFO(err);
  REQUIRE(code == 0);
  CHECK(err.empty());
  const Json out = parse(slurp(w.file("out.json")));
  REQUIRE(out["sub_machines"].items.size() == 4);
  const std::vector<std::vector<double>> converted = conversions(sim.client());
  for (std::size_t n = 0; n < 4; ++n) {
    REQUIRE(converted[n].size() == 3);
    CHECK(distance(converted[n], to_sub(out["sub_machines"].items[n]["global_T_sub"].numbers(), kPoint)) < 1e-9);
  }
  CHECK(read_var(sim.client(), v::kUnlock) == 0.0);

  const std::string page = slurp(w.file("report/index.html"));
  CHECK(page.find("<html") != std::string::npos);
  CHECK(page.find("gantry frames (M2)") != std::string::npos);
  CHECK(page.find("sp4 (global frame)") != std::string::npos);  // the table of the frames
  const Json figures = parse(slurp(w.file("report/module_figures.json")));
  CHECK(figures["sub_machine_figures"].items.size() == 4);
  std::vector<std::string> pngs;
  DIR* dir = ::opendir(w.file("report").c_str());
  REQUIRE(dir != nullptr);
  while (const dirent* e = ::readdir(dir)) {
    const std::string name = e->d_name;
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".png") == 0) pngs.push_back(name);
  }
  ::closedir(dir);
  CHECK(pngs.size() == 6);
  for (const std::string& name : pngs) {
    CAPTURE(name);
    CHECK(page.find(name) != std::string::npos);
    const std::string png = slurp(w.file("report/" + name));
    CHECK(png.size() > 1000);
    CHECK(png.compare(0, 8, std::string("\x89PNG\r\n\x1a\n", 8)) == 0);
  }
}
