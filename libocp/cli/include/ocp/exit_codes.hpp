#pragma once
// The exit codes of every executable (docs/usage.md, "Exit codes"), one table for all:
//   0   passed / normal end (a simulator's --duration-s elapsed, or it was stopped by a signal)
//   1   a verdict or a gate failed (ocp_conformance, ocp_scenario, ocp_bench, ocp_campaign)
//   2   bad command line, or the run could not be done: a harness error, a port in use included
//   130 a verdict tool was interrupted (Ctrl-C): its reports cover what finished, marked so
namespace ocp::cli {

inline constexpr int exit_ok = 0;
inline constexpr int exit_failed = 1;
inline constexpr int exit_usage_error = 2;   // also every harness error: the run could not be done
inline constexpr int exit_interrupted = 130;   // 128 + SIGINT, as a shell reports it

}  // namespace ocp::cli
