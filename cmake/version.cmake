# Writes liftcheck_version.hpp with the current git commit; rewrites it only when it changes.
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY "${SRC_DIR}"
                OUTPUT_VARIABLE LIFTCHECK_COMMIT OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR LIFTCHECK_COMMIT STREQUAL "")
  set(LIFTCHECK_COMMIT "unknown")
else()
  execute_process(COMMAND git status --porcelain --untracked-files=no WORKING_DIRECTORY "${SRC_DIR}"
                  OUTPUT_VARIABLE dirty OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(NOT dirty STREQUAL "")
    string(APPEND LIFTCHECK_COMMIT "-dirty")
  endif()
endif()
configure_file("${IN_FILE}" "${OUT_FILE}.new" @ONLY)
file(COPY_FILE "${OUT_FILE}.new" "${OUT_FILE}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUT_FILE}.new")
