#pragma once
// Reading a process's small /proc files and splitting /proc/PID/stat, once for the harness's
// CPU count of a launched client (process_group_cpu.cpp) and for the virtual-time Controller's
// looks at a client's threads (vtime/src/proc_scan.cpp); and the CPU an rusage counts. Linux only.
#include <sys/resource.h>

#include <cstddef>
#include <string>
#include <vector>

namespace ocp::sim_app {

// A small /proc file (stat, schedstat, children), at most `max_bytes` of it: "" when it cannot
// be read (the process ended meanwhile). A /proc file says its size is 0, so the bound is the
// caller's, not the file's.
std::string read_small_proc_file(const char* path, std::size_t max_bytes = 1023);

// The fields of a stat line after the command name, split at single spaces: [0] is the state
// (field 3 in proc(5)), [n] field n + 3. The command name, in parentheses, may hold any bytes,
// spaces and ')' included, so it ends at the LAST ')'. Empty without a ')'; a line cut short
// gives the fields it holds (the last one perhaps cut too).
std::vector<std::string> stat_fields(const std::string& text);

// User + system seconds of a getrusage or wait4 result.
double cpu_seconds(const rusage& usage);

}  // namespace ocp::sim_app
