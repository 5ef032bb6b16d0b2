# The three protocol cores (Streamer, Player, vehicle client) are sans-IO: they never touch a
# socket, a file, a thread, a clock or a device (ARCHITECTURE.md property 1), and they know the
# com channel only as an ocp::Link. ocp_require_no_asio(target) marks a core;
# ocp_check_core_targets() — called once every target exists — fails the configure step if any
# marked core
#  * links Asio/Boost, the project's Asio adapters (ocp_asio), the link simulator (ocp_link),
#    the UDP com channel (ocp_com) or the file reader (ocp_files), directly or through another
#    library; or
#  * has a source or header (its sources, and every file under its folder) that includes an
#    I/O header: Boost/Asio, <fstream>, <thread>, <mutex>, a Linux device header, the project's
#    Asio adapters (ocp/asio/…), or the file reader (ocp/bounded_file.hpp).
# This is the build's guard against a shortcut; tests/build_check proves it fails such a core.
set_property(GLOBAL PROPERTY OCP_CORE_TARGETS "")
set(OCP_CORE_FORBIDDEN_INCLUDES
    "^[ \t]*#[ \t]*include[ \t]*[<\"](boost/|asio|linux/|fstream>|thread>|mutex>|ocp/asio/|ocp/bounded_file|ocp/com_channel|ocp/impairments)")

function(ocp_require_no_asio target)
  set_property(GLOBAL APPEND PROPERTY OCP_CORE_TARGETS ${target})
endfunction()

# Every library `target` links, transitively (targets only; plain names are kept as they are).
function(_ocp_link_closure target out_var)
  set(seen "")
  set(pending ${target})
  while(pending)
    list(POP_FRONT pending current)
    if(current IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${current})
    if(TARGET ${current})
      get_target_property(aliased ${current} ALIASED_TARGET)
      if(aliased)
        list(APPEND pending ${aliased})
      endif()
      get_target_property(type ${current} TYPE)
      set(links "")
      if(NOT type STREQUAL "INTERFACE_LIBRARY")
        get_target_property(direct ${current} LINK_LIBRARIES)
        if(direct)
          list(APPEND links ${direct})
        endif()
      endif()
      get_target_property(interface ${current} INTERFACE_LINK_LIBRARIES)
      if(interface)
        list(APPEND links ${interface})
      endif()
      foreach(link IN LISTS links)
        string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" link "${link}")
        list(APPEND pending ${link})
      endforeach()
    endif()
  endwhile()
  set(${out_var} ${seen} PARENT_SCOPE)
endfunction()

function(ocp_check_core_targets)
  get_property(cores GLOBAL PROPERTY OCP_CORE_TARGETS)
  foreach(core IN LISTS cores)
    _ocp_link_closure(${core} closure)
    foreach(link IN LISTS closure)
      if(link MATCHES "^(ocp_asio|ocp_link|ocp_com|ocp_files|Boost::|boost_)" OR link MATCHES "asio")
        message(FATAL_ERROR "core target '${core}' links '${link}': cores must stay sans-IO "
                            "(no Asio, no link simulator, no file reader). Move the I/O part "
                            "into an app or adapter target.")
      endif()
    endforeach()
    get_target_property(sources ${core} SOURCES)
    get_target_property(source_dir ${core} SOURCE_DIR)
    file(GLOB_RECURSE folder_files "${source_dir}/*.hpp" "${source_dir}/*.cpp" "${source_dir}/*.h")
    set(files "")
    foreach(source IN LISTS sources folder_files)
      if(NOT IS_ABSOLUTE "${source}")
        set(source "${source_dir}/${source}")
      endif()
      list(APPEND files "${source}")
    endforeach()
    list(REMOVE_DUPLICATES files)
    foreach(file IN LISTS files)
      file(STRINGS "${file}" includes REGEX "${OCP_CORE_FORBIDDEN_INCLUDES}")
      if(includes)
        message(FATAL_ERROR "core target '${core}': ${file} includes ${includes}: cores must "
                            "stay sans-IO (no Asio, no file, thread or lock, no device).")
      endif()
    endforeach()
  endforeach()
endfunction()
