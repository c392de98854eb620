# cmake -DSOURCE_DIR=... -DOUT=... -P source_revision.cmake
# Writes OUT, a C++ source defining trueaxis::sim::kSourceRevision as `git
# describe --always --dirty` of SOURCE_DIR ("unknown" without git or outside a
# checkout). Run at every build (the custom target trueaxis_source_revision),
# it rewrites OUT only when the text changes, so a build after a commit or an
# edit of a tracked file relinks the programs and a build without one does not.
execute_process(
  COMMAND git -C "${SOURCE_DIR}" describe --always --dirty
  OUTPUT_VARIABLE revision
  RESULT_VARIABLE status
  OUTPUT_STRIP_TRAILING_WHITESPACE
  ERROR_QUIET)
if(NOT status EQUAL 0 OR revision STREQUAL "")
  set(revision "unknown")
endif()
file(WRITE "${OUT}.tmp"
  "// Written by host_sim/program/source_revision.cmake at build time.\n"
  "namespace trueaxis::sim {\n"
  "extern const char* const kSourceRevision;\n"
  "const char* const kSourceRevision = \"${revision}\";\n"
  "}  // namespace trueaxis::sim\n")
file(COPY_FILE "${OUT}.tmp" "${OUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUT}.tmp")
