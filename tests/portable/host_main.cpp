// Host runner of the portable tests: output to stdout, exit status 1 on failure.
// --help says what it is and runs nothing (tests/sim/tools/test_commands.py).
#include <cstdio>
#include <cstring>

#include "portable_test.hpp"

namespace {

void stdout_sink(const char* text) { std::fwrite(text, 1, std::strlen(text), stdout); }

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::strcmp(argv[1], "--help") == 0) {
    std::printf("usage: %s\nRuns the portable tests of its module set (tests/portable) and prints one line per case.\n",
                argv[0]);
    return 0;
  }
  return trueaxis::test::TestCase::run_all(stdout_sink) == 0 ? 0 : 1;
}
