# Installing (issue 39, README "Install"): `cmake --install build --prefix P` and the Debian
# package (cmake/package.cmake) lay out
#   P/bin/                      the programs (never the tests or the benchmark binaries)
#   P/lib/ocp-sim/              libocp_vtime_shim.so, preloaded into a client in virtual time
#   P/share/ocp-sim/            their data, found at run time from the program's own place
#                               (apps/sim_app/include/sim_app/data_dir.hpp), never a compiled-in path:
#     web/                      the web view (player_sim's default --webview-root), vendored uPlot included
#     campaign/profiles/        ocp_campaign's shipped profiles (--profile default, calm, …)
#     scenario/library/, scenario/traces/   the scenario library and the link traces it reads
#     schemas/                  the JSON Schemas of the four messages and of scenario files
#     wireshark/ocp.lua         the Lua dissector (docs/wireshark.md)
#     examples/, docs/          the minimal Python clients, the documentation
#   P/share/doc/ocp-sim/        the licence texts: copyright (ours, and what we ship of others), uPlot's
#
# The build tree holds the same data folder, build/share/ocp-sim, as links into the source tree
# (and build/web), so a program run from build/bin finds its data by the same rule as an
# installed one, and an edit to a profile or a page needs no rebuild.
include(GNUInstallDirs)

set(OCP_DATA_DESTINATION ${CMAKE_INSTALL_DATADIR}/ocp-sim)
set(OCP_DOC_DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/ocp-sim)

# ocp_install_programs(): every user program (ocp_user_program) that this build made; the
# target ocp_programs builds just them and the web view's files, what installing needs
# (scripts/package).
function(ocp_install_programs)
  add_custom_target(ocp_programs)
  add_dependencies(ocp_programs webview_assets)
  foreach(program streamer_sim player_sim vehicle_client ocp_scenario ocp_conformance ocp_campaign ocp_bench)
    if(TARGET ${program})
      install(TARGETS ${program} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
      add_dependencies(ocp_programs ${program})
    endif()
  endforeach()
endfunction()
ocp_install_programs()
# The virtual-time shim (vtime/, docs/virtual-time.md), where the programs look for it
# (vtime::find_shim: ../lib/ocp-sim/ beside bin/): `--time virtual` (ocp_campaign --client's
# default, ocp_scenario -- CMD's) works from an installed tree.
if(TARGET ocp_vtime_shim)
  install(TARGETS ocp_vtime_shim LIBRARY DESTINATION lib/ocp-sim)
  add_dependencies(ocp_programs ocp_vtime_shim)
endif()

# The web view: what web/copy_assets.cmake copies into build/web (what a browser loads: never
# node_modules or the browser tests).
install(FILES web/index.html web/favicon.svg DESTINATION ${OCP_DATA_DESTINATION}/web)
install(DIRECTORY web/sdk web/dashboard web/minimal DESTINATION ${OCP_DATA_DESTINATION}/web)
install(FILES web/vendor/uPlot.iife.min.js web/vendor/uPlot.min.css web/vendor/uPlot.LICENSE
        DESTINATION ${OCP_DATA_DESTINATION}/web/vendor)

install(DIRECTORY campaign/profiles DESTINATION ${OCP_DATA_DESTINATION}/campaign FILES_MATCHING PATTERN "*.yaml")
install(DIRECTORY scenario/library scenario/traces DESTINATION ${OCP_DATA_DESTINATION}/scenario)
file(GLOB OCP_MESSAGE_SCHEMAS ${PROJECT_SOURCE_DIR}/docs/schemas/*.schema.json)
install(FILES ${OCP_MESSAGE_SCHEMAS} scenario/scenario.schema.json DESTINATION ${OCP_DATA_DESTINATION}/schemas)
install(FILES scripts/wireshark/ocp.lua DESTINATION ${OCP_DATA_DESTINATION}/wireshark)
install(PROGRAMS examples/vehicle_client.py examples/operator_client.py DESTINATION ${OCP_DATA_DESTINATION}/examples)
install(DIRECTORY docs/ DESTINATION ${OCP_DATA_DESTINATION}/docs PATTERN "*.dot" EXCLUDE)
install(FILES README.md DESTINATION ${OCP_DATA_DESTINATION}/docs)

install(FILES cmake/copyright DESTINATION ${OCP_DOC_DESTINATION})
install(FILES web/vendor/uPlot.LICENSE DESTINATION ${OCP_DOC_DESTINATION})

# The build tree's data folder: links, made at configure time (they name source paths, which is
# fine in the build tree; no program has them compiled in).
function(ocp_stage_build_data)
  set(stage ${CMAKE_BINARY_DIR}/share/ocp-sim)
  file(MAKE_DIRECTORY ${stage}/campaign ${stage}/scenario ${stage}/schemas ${stage}/wireshark)
  set(links
      web ${CMAKE_BINARY_DIR}/web
      campaign/profiles ${PROJECT_SOURCE_DIR}/campaign/profiles
      scenario/library ${PROJECT_SOURCE_DIR}/scenario/library
      scenario/traces ${PROJECT_SOURCE_DIR}/scenario/traces
      wireshark/ocp.lua ${PROJECT_SOURCE_DIR}/scripts/wireshark/ocp.lua
      examples ${PROJECT_SOURCE_DIR}/examples
      docs ${PROJECT_SOURCE_DIR}/docs)
  foreach(schema IN LISTS OCP_MESSAGE_SCHEMAS ITEMS ${PROJECT_SOURCE_DIR}/scenario/scenario.schema.json)
    get_filename_component(name ${schema} NAME)
    list(APPEND links schemas/${name} ${schema})
  endforeach()
  list(LENGTH links count)
  math(EXPR last "${count} - 1")
  foreach(i RANGE 0 ${last} 2)
    math(EXPR j "${i} + 1")
    list(GET links ${i} name)
    list(GET links ${j} target)
    if(NOT IS_SYMLINK ${stage}/${name})
      file(CREATE_LINK ${target} ${stage}/${name} SYMBOLIC)
    endif()
  endforeach()
endfunction()
ocp_stage_build_data()
