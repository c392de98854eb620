// Host runner of the portable tests: output to stdout, exit status 1 on failure.
#include <cstdio>
#include <cstring>

#include "portable_test.hpp"

namespace {

void stdout_sink(const char* text) { std::fwrite(text, 1, std::strlen(text), stdout); }

}  // namespace

int main() { return trueaxis::test::TestCase::run_all(stdout_sink) == 0 ? 0 : 1; }
