#!/usr/bin/env python3
"""The com channel's benchmarks (issue #22), recorded in docs/benchmarks.md. Not a ctest.

    com_bench.py BUILD_BIN_DIR EXAMPLES_DIR [SECONDS]

1. Latency, one process against two, in the same run, no added impairment (--link-delay-ms 0):
   one process:  player_sim --vehicle-tcp truck=PORT (its Streamer in-process, an in-memory link)
   two processes: streamer_sim --com-listen 127.0.0.1:P + player_sim --vehicle truck=udp://…
   each with the reference vehicle_client on TCP and an operator client (examples/
   operator_client.py's protocol) returning the pairs; the samples are the operator feedback's
   message_latency_roundtrip (ms, SPEC §4.1), after a 2 s warm-up. Prints p50 / p90 of each.
2. CPU: the two-process setup with 4 cameras at 30 fps (25 kB frames, the simulator's default
   size): CPU time of streamer_sim and player_sim from /proc/PID/stat over SECONDS (default 20).
"""
import json
import os
import select
import signal
import socket
import subprocess
import sys
import time

sys.path.insert(0, sys.argv[2])
from operator_client import Deframer, answer, frame  # noqa: E402

BIN = sys.argv[1]
SECONDS = float(sys.argv[3]) if len(sys.argv) > 3 else 20.0
TICKS = os.sysconf("SC_CLK_TCK")


def free_port():
    with socket.socket() as tcp:
        tcp.bind(("127.0.0.1", 0))
        return tcp.getsockname()[1]


def listening_port(log_path, pattern, deadline=20):
    end = time.monotonic() + deadline
    while time.monotonic() < end:
        for line in open(log_path):
            if pattern in line:
                return int(line.split(pattern)[1].split()[0].rsplit(":", 1)[1])
        time.sleep(0.1)
    raise SystemExit(f"{pattern!r} never appeared in {log_path}")


def collect_latency(port, seconds, warmup=2.0):
    """message_latency_roundtrip samples seen by an operator client that returns every pair."""
    sock = socket.create_connection(("127.0.0.1", port), timeout=5)
    deframer, active, samples = Deframer(), None, []
    start = time.monotonic()
    while time.monotonic() - start < warmup + seconds:
        if not select.select([sock], [], [], 0.5)[0]:
            continue
        for payload in deframer.feed(sock.recv(65536)):
            shared = json.loads(payload)
            reply, active = answer(shared, active)
            if reply is not None:
                sock.sendall(frame(reply))
            latency = next(iter(shared["vehicle_feedback"].values())).get("message_latency_roundtrip")
            if time.monotonic() - start >= warmup and isinstance(latency, int):
                samples.append(latency)
    sock.close()
    return sorted(samples)


def cpu_seconds(pid):
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS   # utime + stime


class Run:
    def __init__(self):
        self.processes = []

    def start(self, args, log):
        self.processes.append(subprocess.Popen(args, stdout=open(log, "w"), stderr=subprocess.STDOUT))
        return self.processes[-1]

    def stop(self):
        for process in reversed(self.processes):
            process.send_signal(signal.SIGTERM)
            process.wait(timeout=20)


def one_process(seconds):
    run, vehicle_port, operator_port = Run(), free_port(), free_port()
    try:
        run.start([f"{BIN}/player_sim", "--no-webview", "--link-delay-ms", "0", "--vehicle", "truck",
                   "--vehicle-tcp", f"truck={vehicle_port}", "--plugin-param", "ocp_player_tcp_port", str(operator_port)],
                  "/tmp/com_bench_one.log")
        time.sleep(1)
        run.start([f"{BIN}/vehicle_client", "--no-status", f"127.0.0.1:{vehicle_port}"], "/tmp/com_bench_vc1.log")
        return collect_latency(operator_port, seconds)
    finally:
        run.stop()


def two_processes(seconds, cameras=("front",), measure_cpu=False):
    run, operator_port = Run(), free_port()
    camera_args = [arg for name in cameras for arg in ("--camera", f"{name}:30")]
    try:
        streamer = run.start([f"{BIN}/streamer_sim", "--link-delay-ms", "0", "--vehicle", "truck", "--plugin-param",
                              "tcp_port", "0", "--com-listen", "127.0.0.1:0", "--com-insecure", *camera_args],
                             "/tmp/com_bench_streamer.log")
        com_port = listening_port("/tmp/com_bench_streamer.log", "com channel: listening on UDP ")
        vehicle_port = listening_port("/tmp/com_bench_streamer.log", "vehicle API listening on ")
        run.start([f"{BIN}/vehicle_client", "--no-status", f"127.0.0.1:{vehicle_port}"], "/tmp/com_bench_vc2.log")
        player = run.start([f"{BIN}/player_sim", "--no-webview", "--link-delay-ms", "0", "--vehicle",
                            f"truck=udp://127.0.0.1:{com_port}", "--com-insecure", "--plugin-param",
                            "ocp_player_tcp_port", str(operator_port)], "/tmp/com_bench_player.log")
        time.sleep(1)
        if not measure_cpu:
            return collect_latency(operator_port, seconds)
        before = (time.monotonic(), cpu_seconds(streamer.pid), cpu_seconds(player.pid))
        samples = collect_latency(operator_port, seconds, warmup=0)
        after = (time.monotonic(), cpu_seconds(streamer.pid), cpu_seconds(player.pid))
        wall = after[0] - before[0]
        return samples, (after[1] - before[1]) / wall, (after[2] - before[2]) / wall, wall
    finally:
        run.stop()


def percentile(samples, p):
    return samples[min(len(samples) - 1, int(p * len(samples)))] if samples else None


def main():
    latency_seconds = min(SECONDS, 15.0)
    one = one_process(latency_seconds)
    two = two_processes(latency_seconds)
    print(f"latency, one process:   p50 {percentile(one, 0.5)} ms, p90 {percentile(one, 0.9)} ms ({len(one)} samples)")
    print(f"latency, two processes: p50 {percentile(two, 0.5)} ms, p90 {percentile(two, 0.9)} ms ({len(two)} samples)")
    _, streamer_cpu, player_cpu, wall = two_processes(SECONDS, ("front", "rear", "left", "right"), measure_cpu=True)
    with open("/tmp/com_bench_streamer.log") as log:
        status = [line for line in log if "status:" in line][-1:]
    print(f"CPU, 4 cameras x 30 fps x 25 kB over UDP, {wall:.1f} s: streamer_sim {100 * streamer_cpu:.1f} %, "
          f"player_sim {100 * player_cpu:.1f} % of one core")
    print("last Streamer status:", status[0].strip() if status else "none")


if __name__ == "__main__":
    main()
