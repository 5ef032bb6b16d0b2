#pragma once
// Ctrl-C for scenario runs. SIGINT and SIGTERM set a flag; a run polls it (RunOptions::interrupted)
// and stops where it is, so that its verdicts can say what was not judged and the tool can
// still write its reports and exit with interrupted_exit_code.
namespace ocp::scenario {

inline constexpr int interrupted_exit_code = 130;   // 128 + SIGINT, as shells report Ctrl-C

// Installs the handlers. Call again after a real-time run: its signal handling (asio's) puts
// the default action back when it ends.
void catch_interrupts();
bool interrupt_requested();
// What the handlers do (async-signal-safe); tests call it directly.
void request_interrupt();
void clear_interrupt();

}  // namespace ocp::scenario
