# Writes OUTPUT (ocp_git_describe.inc) with `git describe --always --dirty` of SOURCE, run at
# every build (cmake -DSOURCE=… -DOUTPUT=… -P git_describe.cmake), and rewrites it only when
# the text changes, so an unchanged checkout recompiles nothing. Outside a git checkout (a
# source tarball) the describe is "unknown".
find_package(Git QUIET)
set(describe "unknown")
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} -C ${SOURCE} describe --always --dirty
                  OUTPUT_VARIABLE out RESULT_VARIABLE status OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(status EQUAL 0 AND NOT out STREQUAL "")
    set(describe "${out}")
  endif()
endif()
set(content "#define OCP_GIT_DESCRIBE \"${describe}\"\n")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
  if(old STREQUAL content)
    return()
  endif()
endif()
file(WRITE ${OUTPUT} "${content}")
