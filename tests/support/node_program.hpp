#pragma once
// Node.js for the tests that run the Node examples (the conformance suites, virtual time): the
// one node CMake found (find_program(OCP_NODE) in tests/CMakeLists.txt, passed as OCP_NODE_PATH,
// "" when none), so every suite runs the same binary and skips for the same reason.
#include <gtest/gtest.h>

#include <string>

#ifndef OCP_NODE_PATH
#error "OCP_NODE_PATH: give the test target ocp_test_uses_node() in tests/CMakeLists.txt"
#endif

namespace ocp::testing {

inline std::string node_program() { return OCP_NODE_PATH; }

}  // namespace ocp::testing

// In a TEST body: skips the test, with the reason, where node is not installed.
#define OCP_SKIP_WITHOUT_NODE()                  \
  if (::ocp::testing::node_program().empty()) \
  GTEST_SKIP() << "node is not installed (scripts/setup --test installs it)"
