#pragma once
// Exit codes shared by the simulator executables (documented in docs/usage.md).
namespace ocp::sim_app {

inline constexpr int exit_ok = 0;             // normal end: --duration-s elapsed, SIGINT/SIGTERM, --help
inline constexpr int exit_runtime_error = 1;  // e.g. the TCP port is already in use
inline constexpr int exit_usage_error = 2;    // unknown option, bad value, unknown plugin parameter

}  // namespace ocp::sim_app
