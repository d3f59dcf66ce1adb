# Writes OUT (hsbd_version.h) from IN with the current git commit; run at every build,
# touching OUT only when its text changes (so nothing rebuilds needlessly).
execute_process(COMMAND git rev-parse --short=12 HEAD
                WORKING_DIRECTORY ${SRC}
                OUTPUT_VARIABLE HSBD_GIT OUTPUT_STRIP_TRAILING_WHITESPACE
                ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR HSBD_GIT STREQUAL "")
  set(HSBD_GIT "unknown")
endif()
execute_process(COMMAND git status --porcelain --untracked-files=no
                WORKING_DIRECTORY ${SRC}
                OUTPUT_VARIABLE dirty OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT dirty STREQUAL "")
  set(HSBD_GIT "${HSBD_GIT}-modified")
endif()
set(PROJECT_VERSION ${VERSION})
configure_file(${IN} ${OUT}.new @ONLY)
file(READ ${OUT}.new new_text)
if(EXISTS ${OUT})
  file(READ ${OUT} old_text)
else()
  set(old_text "")
endif()
if(NOT new_text STREQUAL old_text)
  file(RENAME ${OUT}.new ${OUT})
else()
  file(REMOVE ${OUT}.new)
endif()
