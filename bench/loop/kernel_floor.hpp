#pragma once
// The kernel floor of a loopback fleet point: what the kernel's TCP stack alone costs for the
// point's traffic, with no simulator code at all. N loopback TCP_NODELAY connections, one
// thread, blocking sockets, batched rounds; each round is one 100 Hz tick of the fleet: a
// control-sized frame sent on every server side, read and answered with a response-sized
// frame on every client side, the responses read back. No epoll, no timers, no user work
// beyond the calls themselves, so the CPU it takes is a lower bound for any process that
// carries this traffic (a getppid costs ~0.2 µs on the bench machine; a vehicle-tick here
// costs ~15 µs, so it is TCP work, not syscall entry). Compared with the machine's cores it
// says whether a target such as "1 000 vehicles at 100 Hz on 2 cores" is reachable at all.
// The paced floor (below) is the same traffic at the point's own beat: what no process that
// paces it at 100 Hz can go below on this machine.
#include <cstddef>
#include <cstdint>
#include <string>

namespace ocp::bench {

struct KernelFloor {
  bool ok = false;
  std::string error;
  std::uint64_t vehicle_ticks = 0;   // connections × rounds measured
  double cpu_s = 0;                   // user + system CPU over the rounds (paced: all its threads')
  double wall_s = 0;                  // over the measured rounds (paced: at least their periods)
  double us_per_vehicle_tick = 0;     // CPU µs per connection per round
  // CPU seconds per wall second the traffic alone needs at 100 Hz: µs per vehicle-tick × N × 100.
  double cpu_per_s_at_100hz = 0;
};

// The same traffic paced as a fleet point runs it: `server_threads` threads (the point's Streamer
// threads) each own a contiguous share of the connections and, every 10 ms, send them in
// `slots` bursts spread over the period, thread i of n offset by i/n of a slot (as
// World::ticker_for phases its tickers), and read each burst's responses back. With
// `client_threads_of_their_own` every server thread has a client thread that reads its frames in
// order and answers (the point's clients on threads of their own); without, the server thread
// answers them itself between the burst and its reads (--client-threads 0). Still no epoll, no
// timers beyond the sleep, no user work: the kernel's TCP plus what waking to a 100 Hz beat
// costs, which no paced process avoids and the batched floor never pays.
struct PacedShape {
  int connections = 1;
  int server_threads = 1;
  bool client_threads_of_their_own = true;
  int slots = 1;
};

// server_threads in [1, connections], slots ≥ 1. CPU is the floor's threads' own
// (CLOCK_THREAD_CPUTIME_ID, summed), after two unmeasured periods, over about `duration_s` (at
// least three periods).
KernelFloor measure_paced_kernel_floor(const PacedShape& shape, std::size_t control_bytes, std::size_t response_bytes,
                                       double duration_s);

// Opens `connections` loopback connection pairs (raising RLIMIT_NOFILE's soft limit towards the
// hard one if 2 × connections do not fit), runs three unmeasured rounds, then measures rounds
// of `control_bytes` out and `response_bytes` back per connection for about `duration_s` (at
// least three rounds), and closes everything.
KernelFloor measure_kernel_floor(int connections, std::size_t control_bytes, std::size_t response_bytes,
                                 double duration_s);

// The cores this process may run on (sched_getaffinity; hardware_concurrency as fallback).
int usable_cores();

}  // namespace ocp::bench
