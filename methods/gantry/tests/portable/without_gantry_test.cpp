// A module set without M2 (the cradle set, levelling alone): its macros
// 9820..9826 answer unknown_macro and its variables (#700.., #3000..) are not
// defined (absent_method.hpp).
#include "absent_method.hpp"
#include "portable_test.hpp"

TA_TEST("without gantry, 9820..9826 answer unknown_macro and #700..#799, #3000..#3999 are undefined") {
  trueaxis::test::check_absent({"gantry", 9820, 9826, 700, 799, 3000, 3999});
}
