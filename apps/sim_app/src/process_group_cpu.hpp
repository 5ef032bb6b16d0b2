#pragma once
// The CPU a process group has used so far, from /proc: what a harness can still count of a
// client it launched through `/bin/sh -c`, whose real process is the shell's child. Killed with
// its group, that child is reaped by init, not by the harness, so getrusage(RUSAGE_CHILDREN)
// never sees its CPU.
#include <sys/types.h>

namespace ocp::sim_app {

// User + system seconds of every live (or not yet reaped) process whose process group is
// `group`, each with what it had reaped of its own children (cutime, cstime). 0 when none.
double process_group_cpu_seconds(pid_t group);

}  // namespace ocp::sim_app
