#pragma once
// The simulator's side of virtual time for external client processes (docs/virtual-time.md).
//
// A Controller owns a VirtualExecutor's clock for the processes it runs: they load the shim
// (vtime/shim) through LD_PRELOAD and the environment() given here. The OCP connections stay
// real loopback TCP sockets: listen() opens one, and every accepted connection becomes a
// ByteStream whose writes are held until the instant is done, then written to the socket.
//
// run_until() is the loop: wait until every thread of every client process is blocked (the
// shim says so for the waits it wraps; /proc confirms every thread is asleep and did not run
// between two looks); take what the clients wrote, at that instant; run the simulator's events
// of the instant; write, and let the clients look again. When nothing is left at this instant,
// jump to the next one: the earliest of the executor's next event and the clients' deadlines.
#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "ocp/byte_stream.hpp"
#include "ocp/virtual_executor.hpp"

namespace ocp::vtime {

// The client cannot live in virtual time (no shim, a busy loop, a hang): the run ends.
class VirtualTimeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ControllerOptions {
  std::string shim_path;   // the shim library (find_shim())
  // A client process that never says hello (a static binary, Go) is found out this soon.
  std::chrono::milliseconds handshake_timeout{2000};
  // CPU a client may burn without ever waiting before it is a busy loop; and the wall time,
  // for a busy client starved of CPU by a loaded machine (it never burns busy_cpu).
  std::chrono::milliseconds busy_cpu{3000};
  std::chrono::milliseconds busy_wall{20'000};
  // Wall time for the whole run: a client that hangs never hangs the tool.
  std::chrono::milliseconds watchdog{120'000};
  // Every wait of every thread, one line each ("" → none): how to debug a hang.
  std::string wait_trace_path;
  // The controller's thread and the clients it launches share one CPU (cpu_pin.hpp): several
  // times faster on a virtual machine. Off also with OCP_VTIME_NO_PIN=1 in the environment.
  bool pin_cpu = true;
};

struct ControllerStats {
  std::uint64_t instants = 0;        // distinct virtual instants visited
  std::uint64_t settles = 0;         // quiescence waits
  std::uint64_t proc_checks = 0;     // /proc looks
  std::uint64_t single_looks = 0;    // of which one look was enough (the pinned CPU)
  std::uint64_t messages = 0;        // from the shims
  std::uint64_t bytes_in = 0;
  std::uint64_t bytes_out = 0;
  // Where the wall time went (docs/benchmarks.md): waiting for quiescence (the clients running
  // and the /proc looks), of which the /proc looks alone; the rest is the simulator and the
  // exchange of bytes.
  std::uint64_t settle_us = 0;
  std::uint64_t proc_us = 0;
  std::uint64_t run_us = 0;        // the whole run_until
};

// The shim: $OCP_VTIME_SHIM, else beside the running program (../lib/ocp-sim/, ../lib/).
// Empty when not found.
std::string find_shim();

class Controller {
 public:
  using AcceptHandler = std::function<void(std::shared_ptr<ByteStream>)>;

  Controller(VirtualExecutor& executor, ControllerOptions options);
  ~Controller();
  Controller(const Controller&) = delete;
  Controller& operator=(const Controller&) = delete;

  // What a client process needs in its environment (LD_PRELOAD, the socket, the clock page).
  std::vector<std::string> environment() const;

  // A listening socket on 127.0.0.1:`port` (0: ephemeral). Returns its id; port(id) says where.
  int listen(std::uint16_t port, AcceptHandler on_accept);
  std::uint16_t port(int listener) const;
  // Closed (connections are refused) for `down` of virtual time, then listening again.
  void close_listener_for(int listener, Micros down);

  // A process launched for this world: without a shim hello within handshake_timeout it cannot
  // run in virtual time. `alive` tells whether it still runs. `name` is for messages.
  void expect_process(pid_t pid, std::string name, std::function<bool()> alive);

  // Runs to `end`, or until `interrupted` says so (polled between instants). Returns the time
  // it stopped at. Throws VirtualTimeError.
  SimTime run_until(SimTime end, const std::function<bool()>& interrupted);

  const ControllerStats& stats() const { return stats_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  ControllerStats& stats_;
};

}  // namespace ocp::vtime
