# Writes OUT, a header defining RTT_GIT_COMMIT: the commit the sources are being built from
# ("+dirty" with uncommitted changes to tracked files, "unknown" without git). Run at every
# build (CMakeLists.txt, target rtt_git_commit); OUT is rewritten only when the commit changes,
# so an unchanged tree recompiles nothing.
#   cmake -DSRC=<source dir> -DOUT=<header> -P git_commit.cmake
set(commit "unknown")
execute_process(COMMAND git -C "${SRC}" rev-parse HEAD
                OUTPUT_VARIABLE head RESULT_VARIABLE rc
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(rc EQUAL 0 AND NOT head STREQUAL "")
  set(commit "${head}")
  execute_process(COMMAND git -C "${SRC}" status --porcelain --untracked-files=no
                  OUTPUT_VARIABLE changes RESULT_VARIABLE rc ERROR_QUIET)
  if(rc EQUAL 0 AND NOT changes STREQUAL "")
    set(commit "${head}+dirty")
  endif()
endif()
set(content "#define RTT_GIT_COMMIT \"${commit}\"\n")
set(old "")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT old STREQUAL content)
  file(WRITE "${OUT}" "${content}")
endif()
