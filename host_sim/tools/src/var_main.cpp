// trueaxis-var: the module's variables in decimal, and a macro run to its end,
// over Modbus TCP or RTU: what an operator or an integrator types instead of
// hexadecimal registers (docs/INTERFACE.md "Encoding", "The handshake").
//
// Usage: kHelp below. Conventions:
//  1. Values are read and printed as decimals, printed with %.17g (they read
//     back to the same double). A line of output is "#N = V"; for a macro's
//     result "#N = V (name, unit)" with the name and unit of the register map.
//  2. run writes the G65 letters given (A = #1 .. Z = #26, letters as
//     docs/INTERFACE.md "Arguments"; G, L, N, O, P have no variable), runs the
//     macro (var_session.hpp contract 2) and prints "MACRO NAME: done, error 0
//     ok, S steps, T us", then the macro's results (its MacroInfo outputs; for a
//     macro this map does not know, #100.. up to the last that is not 0). A
//     macro that ends in error is a failure.
//  3. set with an unlock code (#9004) takes the macro interface for itself
//     first (#9009 = 1), so that no other client's macro closes the unlock
//     before the configuration it writes; run holds it only for its macro.
//  4. A failure is one line on stderr, "trueaxis-var: " and what
//     var_session.hpp contract 3 says, or for a macro error "macro N NAME:
//     module error CODE NAME: MESSAGE"; nothing goes to stdout then. Exit 0 on
//     success, 1 on a failure, 2 on bad usage.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "trueaxis/core/status.hpp"
#include "trueaxis/macros/register_map.hpp"
#include "trueaxis/macros/platform_map.hpp"
#include "trueaxis/macros/var_info.hpp"
#include "trueaxis/sim/program.hpp"
#include "trueaxis/sim/tools/client.hpp"
#include "trueaxis/sim/tools/var_session.hpp"

namespace {

namespace var = trueaxis::macros::var;
using trueaxis::sim::Assignment;
using trueaxis::sim::VarSession;

constexpr const char* kHelp =
    "usage: trueaxis-var [--host H] [--port P | --rtu DEVICE [--baud B] [--parity N|E|O] [--slave N]]\n"
    "                    [--timeout MS] [--retries N] [--wait MS] COMMAND ...\n"
    "  get N...             read variables #N (or N..M), print '#N = V' per variable\n"
    "  set N=V...           write variables, decimal values (e.g. set 5281=0 5282=0 5283=40)\n"
    "  run MACRO [L=V...]   write the G65 arguments (A=#1 B=#2 C=#3 I=#4 J=#5 K=#6 D=#7 E=#8\n"
    "                       F=#9 H=#11 M=#13 Q=#17 R=#18 S=#19 T=#20 U=#21 V=#22 W=#23 X=#24\n"
    "                       Y=#25 Z=#26), run the macro (#9000), wait until #9003 grows, print\n"
    "                       its status and results with their names\n"
    "  --host H             Modbus TCP server (default 127.0.0.1)\n"
    "  --port P             its port (default 502)\n"
    "  --rtu DEVICE         Modbus RTU on a serial device instead (8 data bits, 1 stop bit)\n"
    "  --baud B             default 19200\n"
    "  --parity N|E|O       default N\n"
    "  --slave N            the slave address, 1..247 (default 1)\n"
    "  --timeout MS         a request's reply time-out (default 1000)\n"
    "  --retries N          a request without a reply is sent again up to N times (default 0\n"
    "                       over TCP, 3 over RTU); the macro number only when it did not start\n"
    "  --wait MS            how long run waits for the macro to end (default 60000)\n"
    "  --help, --version    this text; the version line\n"
    "Values print with 17 significant digits. Exit 0 on success; 1 on a refusal, a macro error,\n"
    "a time-out or a connection failure (one line on stderr, nothing on stdout); 2 on bad usage.\n";

int usage_error(const std::string& why) {
  std::fprintf(stderr, "trueaxis-var: %s (trueaxis-var --help)\n", why.c_str());
  return 2;
}

int fail(const std::string& why) {
  std::fprintf(stderr, "trueaxis-var: %s\n", why.c_str());
  return 1;
}

bool parse_long(const char* text, long lo, long hi, long& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtol(text, &end, 10);
  return errno == 0 && end != text && *end == '\0' && out >= lo && out <= hi;
}

bool parse_number(const std::string& text, long lo, std::uint16_t& out) {
  long n = 0;
  if (!parse_long(text.c_str(), lo, trueaxis::macros::kMaxVariableNumber, n)) return false;
  out = static_cast<std::uint16_t>(n);
  return true;
}

// A decimal as C strtod reads it, the whole text. NaN and infinities pass: the
// module refuses them, and that answer is the module's to give.
bool parse_value(const std::string& text, double& out) {
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size();
}

std::string decimal(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

// The G65 letter's variable (platform_map.hpp); 0 for G, L, N, O, P.
std::uint16_t letter_variable(char letter) {
  static constexpr std::uint16_t kByLetter[26] = {
      var::kArgA, var::kArgB, var::kArgC, var::kArgD, var::kArgE, var::kArgF, 0,          var::kArgH, var::kArgI,
      var::kArgJ, var::kArgK, 0,          var::kArgM, 0,          0,          0,          var::kArgQ, var::kArgR,
      var::kArgS, var::kArgT, var::kArgU, var::kArgV, var::kArgW, var::kArgX, var::kArgY, var::kArgZ};
  return letter >= 'A' && letter <= 'Z' ? kByLetter[letter - 'A'] : 0;
}

struct Options {
  std::string host = "127.0.0.1";
  std::string device;  // --rtu
  long port = 502, baud = 19200, slave = 1, timeout_ms = 1000, retries = -1, wait_ms = 60000;
  char parity = 'N';
  bool port_given = false;
};

int get(VarSession& s, const std::vector<std::string>& args, const Options&) {
  std::vector<std::uint16_t> numbers;
  for (const std::string& a : args) {
    const std::size_t dots = a.find("..");
    std::uint16_t first = 0;
    std::uint16_t last = 0;
    if (!parse_number(a.substr(0, dots), 0, first) ||
        !parse_number(dots == std::string::npos ? a : a.substr(dots + 2), 0, last) || last < first ||
        last - first >= 1000) {
      return usage_error("get takes variable numbers N or N..M (at most 1000), not '" + a + "'");
    }
    for (std::uint32_t n = first; n <= last; ++n) numbers.push_back(static_cast<std::uint16_t>(n));
  }
  if (numbers.empty()) return usage_error("get needs a variable number");
  std::vector<double> values;
  if (!s.read(numbers, values)) return fail(s.error());
  for (std::size_t i = 0; i < numbers.size(); ++i) std::printf("#%u = %s\n", numbers[i], decimal(values[i]).c_str());
  return 0;
}

int set(VarSession& s, const std::vector<std::string>& args, const Options&) {
  std::vector<Assignment> assignments;
  for (const std::string& a : args) {
    const std::size_t eq = a.find('=');
    Assignment x;
    if (eq == std::string::npos || !parse_number(a.substr(0, eq), 0, x.number) ||
        !parse_value(a.substr(eq + 1), x.value)) {
      return usage_error("set takes N=V (a variable number and a decimal), not '" + a + "'");
    }
    assignments.push_back(x);
  }
  if (assignments.empty()) return usage_error("set needs N=V");
  // An unlock takes no macro interface (macros/module.hpp contract 8), and
  // another client taking it would close this one's unlock before its
  // configuration writes: a command that unlocks holds the interface for
  // itself first (#9009 = 1; the connection's close gives it back).
  const bool unlocks = std::any_of(assignments.begin(), assignments.end(),
                                   [](const Assignment& a) { return a.number == var::kUnlock && a.value != 0.0; });
  if (unlocks) {
    std::vector<Assignment> held = {{var::kInterface, 1.0}};
    held.insert(held.end(), assignments.begin(), assignments.end());
    assignments = held;
  }
  return s.write(assignments) ? 0 : fail(s.error());
}

// Convention 2: the results of a macro this map knows, by its outputs; of
// another, #100.. up to the last that is not 0.
int print_results(VarSession& s, const trueaxis::macros::MacroInfo* info) {
  std::vector<std::uint16_t> numbers;
  if (info != nullptr) {
    for (std::size_t k = 0; k < info->output_count; ++k) numbers.push_back(info->outputs[k].number);
  } else {
    for (std::uint16_t n = var::kResultFirst; n <= var::kResultLast; ++n) numbers.push_back(n);
  }
  std::vector<double> values;
  if (!s.read(numbers, values)) return fail(s.error());
  std::size_t shown = numbers.size();
  if (info == nullptr) {
    while (shown > 0 && values[shown - 1] == 0.0) --shown;
  }
  for (std::size_t k = 0; k < shown; ++k) {
    std::string about;
    if (info != nullptr) {
      const trueaxis::macros::OutputInfo& o = info->outputs[k];
      about = std::string(" (") + o.name + (o.unit[0] != '\0' ? std::string(", ") + o.unit : "") + ")";
    }
    std::printf("#%u = %s%s\n", numbers[k], decimal(values[k]).c_str(), about.c_str());
  }
  return 0;
}

int run(VarSession& s, const std::vector<std::string>& args, const Options& o) {
  std::uint16_t macro = 0;
  if (args.empty() || !parse_number(args[0], 1, macro) || macro > 9999) {
    return usage_error("run takes a macro number 1..9999 first");
  }
  std::vector<Assignment> arguments;
  for (std::size_t k = 1; k < args.size(); ++k) {
    const std::string& a = args[k];
    const char letter = a.size() > 2 && a[1] == '=' ? static_cast<char>(std::toupper(static_cast<unsigned char>(a[0]))) : '?';
    Assignment x;
    x.number = letter_variable(letter);
    if (x.number == 0 || !parse_value(a.substr(2), x.value)) {
      return usage_error("run takes LETTER=V, a G65 letter (not G, L, N, O or P) and a decimal, not '" + a + "'");
    }
    for (const Assignment& y : arguments) {
      if (y.number == x.number) return usage_error(std::string("letter ") + letter + " is given twice");
    }
    arguments.push_back(x);
  }
  // In variable order, so that adjacent letters (A B C, X Y Z) go in one request.
  std::sort(arguments.begin(), arguments.end(),
            [](const Assignment& a, const Assignment& b) { return a.number < b.number; });

  const trueaxis::macros::MacroInfo* info = trueaxis::macros::find_macro(macro);
  const std::string title = std::to_string(macro) + (info != nullptr ? std::string(" ") + info->name : "");
  trueaxis::sim::MacroEnd end;
  if (!s.run(macro, arguments, static_cast<int>(o.wait_ms), end)) return fail(s.error());
  const auto status = static_cast<trueaxis::core::Status>(end.error);
  if (end.status != static_cast<int>(trueaxis::macros::MacroState::kDone)) {
    return fail("macro " + title + ": module error " + std::to_string(end.error) + " " +
                trueaxis::macros::status_name(status) + ": " + trueaxis::macros::status_message(status));
  }
  std::printf("%s: done, error %d %s, %d step%s, %.0f us%s\n", title.c_str(), end.error,
              trueaxis::macros::status_name(status), end.steps, end.steps == 1 ? "" : "s", end.run_time_us,
              info != nullptr ? "" : " (not in this map: its results unnamed)");
  return print_results(s, info);
}

struct Command {
  const char* name;
  int (*run)(VarSession&, const std::vector<std::string>&, const Options&);
};

constexpr Command kCommands[] = {{"get", get}, {"set", set}, {"run", run}};

}  // namespace

int main(int argc, char** argv) {
  if (trueaxis::sim::answered_help_or_version(argc, argv, "trueaxis-var", kHelp)) return 0;
  Options o;
  int i = 1;
  for (; i < argc && argv[i][0] == '-'; i += 2) {
    const std::string opt = argv[i];
    if (i + 1 >= argc) return usage_error("option '" + opt + "' needs a value");
    const char* value = argv[i + 1];
    bool ok = true;
    if (opt == "--host") {
      o.host = value;
    } else if (opt == "--port") {
      ok = parse_long(value, 1, 65535, o.port);
      o.port_given = true;
    } else if (opt == "--rtu") {
      o.device = value;
    } else if (opt == "--baud") {
      ok = parse_long(value, 50, 4000000, o.baud);
    } else if (opt == "--parity") {
      ok = std::strlen(value) == 1 && std::strchr("NEO", value[0]) != nullptr;
      o.parity = value[0];
    } else if (opt == "--slave") {
      ok = parse_long(value, 1, 247, o.slave);
    } else if (opt == "--timeout") {
      ok = parse_long(value, 1, 600000, o.timeout_ms);
    } else if (opt == "--retries") {
      ok = parse_long(value, 0, 100, o.retries);
    } else if (opt == "--wait") {
      ok = parse_long(value, 0, 86400000, o.wait_ms);
    } else {
      return usage_error("unknown option '" + opt + "'");
    }
    if (!ok) return usage_error("bad value for " + opt + ": '" + value + "'");
  }
  if (!o.device.empty() && o.port_given) return usage_error("--port and --rtu exclude each other");
  if (i >= argc) return usage_error("no COMMAND (get, set or run)");
  const Command* command = nullptr;
  for (const Command& c : kCommands) {
    if (std::strcmp(argv[i], c.name) == 0) command = &c;
  }
  if (command == nullptr) return usage_error(std::string("unknown COMMAND '") + argv[i] + "' (get, set or run)");
  const std::vector<std::string> args(argv + i + 1, argv + argc);

  trueaxis::sim::VariableClient client;
  const int timeout_ms = static_cast<int>(o.timeout_ms);
  std::string endpoint;
  if (o.device.empty()) {
    endpoint = o.host + ":" + std::to_string(o.port);
    if (!client.connect(o.host, static_cast<int>(o.port), timeout_ms)) {
      return fail("cannot connect to " + endpoint + ": " + client.error_text());
    }
  } else {
    endpoint = o.device + " (slave " + std::to_string(o.slave) + ")";
    if (!client.connect_rtu(o.device, static_cast<int>(o.baud), o.parity, static_cast<int>(o.slave), timeout_ms)) {
      return fail("cannot open " + o.device + ": " + client.error_text());
    }
  }
  const long retries = o.retries >= 0 ? o.retries : (o.device.empty() ? 0 : 3);
  VarSession session(client, endpoint, timeout_ms, static_cast<int>(retries));
  return command->run(session, args, o);
}
