// A module set without the canary: its macros 9850..9854 answer unknown_macro
// and its variables (#950..#959) are not defined (absent_method.hpp).
#include "absent_method.hpp"
#include "portable_test.hpp"

TA_TEST("without canary, 9850..9854 answer unknown_macro and #950..#959 are undefined") {
  trueaxis::test::check_absent({"canary", 9850, 9854, 950, 959, 950, 959});
}
