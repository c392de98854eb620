// The byte order of the persistent records' payloads: core's little-endian
// encoding (firmware_core byte_order.hpp), named here for the macro layer.
#pragma once

#include "trueaxis/core/byte_order.hpp"

namespace trueaxis::macros {

using core::get_f64;
using core::get_u16;
using core::get_u32;
using core::put_f64;
using core::put_u16;

}  // namespace trueaxis::macros
