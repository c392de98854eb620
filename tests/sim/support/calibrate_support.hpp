// What the trueaxis-calibrate tests share: a child process run by argv (no
// shell) with its exit code, stdout and stderr, files, a temporary directory, a
// report's PNG figures, and a small strict JSON reader for OUT.json.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <dirent.h>
#include <fcntl.h>
#include <ftw.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>

extern char** environ;

namespace trueaxis::test {

// ---- processes and files -------------------------------------------------------------

struct Run {
  int exit_code = -1;
  std::string err;  // all of stderr
  std::string out;  // all of stdout
};

inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline bool exists(const std::string& path) { return ::access(path.c_str(), F_OK) == 0; }

// argv[0] is the binary's path; stderr goes to err_path, stdout to err_path + ".out".
inline Run run(const std::vector<std::string>& argv, const std::string& err_path) {
  const std::string out_path = err_path + ".out";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  Run r;
  const int rc = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(rc == 0);
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.err = slurp(err_path);
  r.out = slurp(out_path);
  return r;
}

inline int remove_entry(const char* path, const struct stat*, int, struct FTW*) { return std::remove(path); }

// A directory /tmp/PREFIX-XXXXXX, removed with all it holds at the end.
struct Workspace {
  std::string dir;
  explicit Workspace(const std::string& prefix) {
    std::string path = "/tmp/" + prefix + "-XXXXXX";
    REQUIRE(::mkdtemp(&path[0]) != nullptr);
    dir = path;
  }
  ~Workspace() { ::nftw(dir.c_str(), remove_entry, 16, FTW_DEPTH | FTW_PHYS); }
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;
  std::string file(const std::string& name) const { return dir + "/" + name; }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name), std::ios::binary | std::ios::trunc) << text;
    return file(name);
  }
};

// ---- a report --------------------------------------------------------------------------

// The names of the PNG files in dir.
inline std::vector<std::string> pngs_in(const std::string& dir) {
  std::vector<std::string> pngs;
  DIR* d = ::opendir(dir.c_str());
  REQUIRE(d != nullptr);
  while (const dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".png") == 0) pngs.push_back(name);
  }
  ::closedir(d);
  return pngs;
}

// The figure dir/name: the page shows it, and it is a PNG of some size.
inline void check_figure(const std::string& page, const std::string& dir, const std::string& name) {
  CAPTURE(name);
  CHECK(page.find(name) != std::string::npos);
  const std::string png = slurp(dir + "/" + name);
  CHECK(png.size() > 1000);
  CHECK(png.compare(0, 8, std::string("\x89PNG\r\n\x1a\n", 8)) == 0);
}

// ---- a small strict JSON reader --------------------------------------------------------

struct Json {
  enum Kind { kNull, kBool, kNumber, kString, kArray, kObject } kind = kNull;
  bool boolean = false;
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
  // An array's items as numbers, NaN for an item that is not one.
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
    while (at_ < s_.size() && (s_[at_] == ' ' || s_[at_] == '\n' || s_[at_] == '\r' || s_[at_] == '\t')) ++at_;
  }
  bool eat(char c) {
    space();
    if (at_ >= s_.size() || s_[at_] != c) return false;
    ++at_;
    return true;
  }
  bool word(const char* w) {
    const std::string text(w);
    if (s_.compare(at_, text.size(), text) != 0) return false;
    at_ += text.size();
    return true;
  }
  bool string(std::string& out) {
    if (!eat('"')) return false;
    while (at_ < s_.size() && s_[at_] != '"') {
      if (s_[at_] == '\\') ++at_;
      if (at_ < s_.size()) out += s_[at_++];
    }
    return eat('"');
  }
  bool value(Json& out) {
    space();
    if (at_ >= s_.size()) return false;
    const char c = s_[at_];
    if (c == '{') {
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
    if (c == '[') {
      out.kind = Json::kArray;
      ++at_;
      if (eat(']')) return true;
      do {
        out.items.emplace_back();
        if (!value(out.items.back())) return false;
      } while (eat(','));
      return eat(']');
    }
    if (c == '"') {
      out.kind = Json::kString;
      return string(out.text);
    }
    if (word("true") || word("false")) {
      out.kind = Json::kBool;
      out.boolean = c == 't';
      return true;
    }
    if (word("null")) {
      out.kind = Json::kNull;
      return true;
    }
    const std::size_t end = s_.find_first_not_of("+-0123456789.eE", at_);
    const std::string token = s_.substr(at_, end - at_);
    char* stop = nullptr;
    out.number = std::strtod(token.c_str(), &stop);
    if (token.empty() || *stop != '\0' || token[0] == '+' || token[0] == '.') return false;
    out.kind = Json::kNumber;
    at_ = end;
    return true;
  }

  const std::string& s_;
  std::size_t at_ = 0;
};

// The text as JSON; the test stops (showing the text) when it is not.
inline Json parse(const std::string& text) {
  Json j;
  INFO(text);
  REQUIRE(JsonReader(text).parse(j));
  return j;
}

}  // namespace trueaxis::test
