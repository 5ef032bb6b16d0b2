# The Debian package (issue 39): `scripts/package` = `cpack -G DEB` in the release build, which
# installs the rules of cmake/install.cmake under /usr into ocp-sim_VERSION_ARCH.deb.
#   version  the project's (project(VERSION) in CMakeLists.txt: the one place, also --version's)
#   Depends  from the programs' real shared-library dependencies (dpkg-shlibdeps)
#   Suggests Wireshark, which loads the Lua dissector (share/ocp-sim/wireshark/ocp.lua)
# tests/install/package_test.sh installs it into a bare Debian 12 root (a CI stage of its own).
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME ocp-sim)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "OCP simulator maintainers <ocp-sim@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Simulator and conformance suites for the Oden Control Pipeline (OCP)")
set(CPACK_PACKAGE_DESCRIPTION
    "Simulates the Oden Streamer's vehicle API and the Player's operator API with a fake com channel,
and grades vehicle-side and operator-side clients: streamer_sim, player_sim (with its web view),
the reference vehicle_client, ocp_conformance, ocp_scenario (with the scenario library),
ocp_campaign and ocp_bench.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION devel)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "wireshark | tshark")
set(CPACK_DEBIAN_COMPRESSION_TYPE xz)
include(CPack)
