// Must not link: it calls malloc, and every target image is linked with the
// allocator wrapped to symbols nothing defines (toolchain/arm-none-eabi.cmake).
// ctest's target_link_rejects_heap builds it and expects the build to fail.
#include <cstdlib>

int main() {
  void* volatile p = std::malloc(16);
  std::free(p);
  return 0;
}
