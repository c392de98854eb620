// A module set without M1 (the gantry set): its macros 9810..9814 answer
// unknown_macro and its variables (#500.., #1000..) are not defined
// (absent_method.hpp).
#include "absent_method.hpp"
#include "portable_test.hpp"

TA_TEST("without level, 9810..9814 answer unknown_macro and #500..#599, #1000..#1999 are undefined") {
  trueaxis::test::check_absent({"level", 9810, 9814, 500, 599, 1000, 1999});
}
