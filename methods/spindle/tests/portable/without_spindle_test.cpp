// A module set without M4 (levelling alone): its macros 9840..9847 answer
// unknown_macro and its variables (#800.., #4000..) are not defined
// (absent_method.hpp).
#include "absent_method.hpp"
#include "portable_test.hpp"

TA_TEST("without spindle, 9840..9847 answer unknown_macro and #800..#899, #4000..#4999 are undefined") {
  trueaxis::test::check_absent({"spindle", 9840, 9847, 800, 899, 4000, 4999});
}
