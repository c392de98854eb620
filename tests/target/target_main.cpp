// Target runner of the portable tests (tests/portable): output over semihosting;
// the exit status (0 when every case passed) becomes QEMU's, and so ctest's.
#include "portable_test.hpp"
#include "trueaxis/hal/mps2/semihosting.hpp"

namespace {

void semihosting_sink(const char* text) { trueaxis::hal::mps2::console_write(text); }

}  // namespace

int main() { return trueaxis::test::TestCase::run_all(semihosting_sink) == 0 ? 0 : 1; }
