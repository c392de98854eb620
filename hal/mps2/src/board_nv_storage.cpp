#include "trueaxis/hal/mps2/board_nv_storage.hpp"

#include <cstdint>

namespace trueaxis::hal::mps2 {
namespace {

// Not zeroed at start-up: battery-backed RAM keeps its content over a reset.
__attribute__((section(".noinit"))) std::uint8_t g_nv_ram[kBoardNvBytes];

}  // namespace

RamNvStorage board_nv_storage() { return RamNvStorage(g_nv_ram, kBoardNvBytes); }

}  // namespace trueaxis::hal::mps2
