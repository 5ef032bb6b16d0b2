# Unity builds whose sources a fresh clone can share through ccache.
#
# CMake's own unity build (CMAKE_UNITY_BUILD) writes `#include "/absolute/path/x.cpp"` into its
# batch files, so a clone at another path has different batch files and ccache finds nothing
# of an earlier checkout. Here each batch file includes its sources by a path relative to the
# batch file, and the batches live under the build tree, so two clones built the same way
# (`scripts/build`) write byte-identical batch files; with CCACHE_BASEDIR at the checkout and no
# hash of the working directory, the second clone's build is all cache hits.
#
# ocp_unity_build(BATCH_SIZE) batches every library and executable target of the project with
# two or more C++ sources, after all targets exist. A batch's sources share one translation
# unit, so a source must not reuse another source's file-local name in the same target.
#
# A source listed in the global property OCP_UNITY_SOLO_SOURCES is never batched: a target
# that compiles its own copy of it (tests/campaign_mutants) must be able to stand in for that
# one object of the library, which a batch holding other sources would not let the linker do.

function(_ocp_targets_in directory out_var)
  get_property(targets DIRECTORY ${directory} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirectories DIRECTORY ${directory} PROPERTY SUBDIRECTORIES)
  foreach(subdirectory IN LISTS subdirectories)
    _ocp_targets_in(${subdirectory} below)
    list(APPEND targets ${below})
  endforeach()
  set(${out_var} ${targets} PARENT_SCOPE)
endfunction()

# Writes `path` only when its content changes, so a reconfigure rebuilds nothing.
function(_ocp_write_if_changed path content)
  if(EXISTS ${path})
    file(READ ${path} old)
    if(old STREQUAL content)
      return()
    endif()
  endif()
  file(WRITE ${path} "${content}")
endfunction()

function(ocp_unity_build batch_size)
  _ocp_targets_in(${PROJECT_SOURCE_DIR} targets)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(NOT type MATCHES "^(STATIC_LIBRARY|EXECUTABLE)$")
      continue()
    endif()
    # A target that compiles copies of other targets' sources (tests/campaign_mutants) opts out:
    # its sources were never batched together anywhere else. So does a hot path whose speed
    # depends on GCC's per-unit inlining budget (ocp_codec, libocp/CMakeLists.txt).
    get_target_property(no_unity ${target} OCP_NO_UNITY)
    if(no_unity)
      continue()
    endif()
    get_target_property(sources ${target} SOURCES)
    get_target_property(source_dir ${target} SOURCE_DIR)
    get_property(solo_sources GLOBAL PROPERTY OCP_UNITY_SOLO_SOURCES)
    set(cpp "")
    set(others "")
    foreach(source IN LISTS sources)
      if(NOT IS_ABSOLUTE ${source})
        set(source ${source_dir}/${source})
      endif()
      if(source IN_LIST solo_sources)
        list(APPEND others ${source})   # its own object: see OCP_UNITY_SOLO_SOURCES below
      elseif(source MATCHES "\\.cpp$")
        list(APPEND cpp ${source})
      else()
        list(APPEND others ${source})
      endif()
    endforeach()
    list(LENGTH cpp count)
    if(count LESS 2)
      continue()
    endif()
    set(batch_dir ${CMAKE_BINARY_DIR}/unity/${target})
    set(batches "")
    set(content "")
    set(in_batch 0)
    set(index 0)
    foreach(source IN LISTS cpp)
      file(RELATIVE_PATH relative ${batch_dir} ${source})
      string(APPEND content "#include \"${relative}\"\n")
      math(EXPR in_batch "${in_batch} + 1")
      if(in_batch EQUAL batch_size)
        _ocp_write_if_changed(${batch_dir}/batch_${index}.cpp "${content}")
        list(APPEND batches ${batch_dir}/batch_${index}.cpp)
        math(EXPR index "${index} + 1")
        set(content "")
        set(in_batch 0)
      endif()
    endforeach()
    if(in_batch GREATER 0)
      _ocp_write_if_changed(${batch_dir}/batch_${index}.cpp "${content}")
      list(APPEND batches ${batch_dir}/batch_${index}.cpp)
    endif()
    # A quoted include in a batched source still finds its neighbours: the compiler looks in
    # the folder of the file that includes first, and that is the source's own folder.
    set_property(TARGET ${target} PROPERTY SOURCES ${batches} ${others})
  endforeach()
endfunction()
