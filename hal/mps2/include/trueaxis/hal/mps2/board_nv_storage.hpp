// The MPS2 board's non-volatile storage: kBoardNvBytes of battery-backed RAM.
//
// Contract
//  1. board_nv_storage() returns a hal::RamNvStorage over one static array in the
//     .noinit section, which the start-up code neither loads nor zeroes, so it
//     keeps its content over a warm reset (QEMU starts every run with it zeroed,
//     like a fresh battery).
//  2. Every object it returns views the same bytes (there is one device): main
//     makes one and passes it by reference.
//  3. Its content after power-up is arbitrary: the user validates it
//     (macros/keyed_store.hpp keeps two copies with a version and a CRC).
//  4. 32 KiB: the product's records need macros::kRequiredStorageBytes (28528 B,
//     macros/records.hpp); tests/target/firmware_main.cpp checks that they fit
//     (hal does not see the macros headers).
#pragma once

#include <cstddef>

#include "trueaxis/hal/ram_nv_storage.hpp"

namespace trueaxis::hal::mps2 {

inline constexpr std::size_t kBoardNvBytes = 32 * 1024;

// The board's storage; C++17 returns it in place (NvStorage cannot be copied).
RamNvStorage board_nv_storage();

}  // namespace trueaxis::hal::mps2
