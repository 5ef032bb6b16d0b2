#!/usr/bin/env python3
"""`ocp_bench fleet` reports each thread of a point (issue #41), and the report is sane.

  fleet_threads.py OCP_BENCH

A tiny run, one loopback point with 2 Streamer threads and 3 client threads and one virtual
point, then a loopback point with the clients on the Streamer's thread (--client-threads 0),
and the ticker slots chosen by the vehicles per Streamer thread. The loopback point names the
Player's thread, each Streamer thread and each client thread exactly once; no thread used more
than a core; the threads' CPU adds up to the process's (getrusage); the text report has the table and names the busiest thread. A report check, not a
timing test: every bound holds on a loaded machine. Prints ✓/✗ per check; exit 1 if one fails.
"""
import json
import pathlib
import subprocess
import sys
import tempfile

failures = []


def check(name, ok, detail=""):
    print(f"{'✓' if ok else '✗'} {name}{'' if ok else ': ' + detail}")
    if not ok:
        failures.append(name)


def run_fleet(bench, arguments):
    """(the report as JSON, the text) of one tiny `ocp_bench fleet` run; None if it failed."""
    with tempfile.TemporaryDirectory(prefix="fleet_threads.") as scratch:
        json_path = pathlib.Path(scratch) / "fleet.json"
        result = subprocess.run(
            [bench, "fleet", "--window-s", "0.5", "--simulated-s", "0.2", "--warm-up-s", "0.2", "--no-kernel-floor",
             "--no-codec-floor", "--json", str(json_path)] + arguments,
            capture_output=True, text=True, timeout=90, stdin=subprocess.DEVNULL)
        check(f"{' '.join(arguments)}: exit 0", result.returncode == 0,
              f"exit {result.returncode}\n{result.stdout}\n{result.stderr}")
        if result.returncode != 0:
            return None
        return json.loads(json_path.read_text()), result


def clients_on_streamer_threads(bench):
    """--client-threads 0: the clients run on the Streamers' threads, so no client thread exists."""
    ran = run_fleet(bench, ["--loopback", "4", "--virtual", "0", "--streamer-threads", "1", "--client-threads", "0"])
    if ran is None:
        return
    point = ran[0]["points"][0]
    names = sorted(thread["name"] for thread in point["threads"])
    check("--client-threads 0: only the Player's and the Streamers' threads", names == ["player", "streamers-0"],
          str(names))
    check("--client-threads 0: every client connected and answered", point["ok"] and point["connections"] == 4
          and point["responses"] > 0, json.dumps(point))


def client_threads_follow_streamer_threads(bench):
    """Without --client-threads there are as many client threads as Streamer threads."""
    ran = run_fleet(bench, ["--loopback", "3", "--virtual", "0", "--streamer-threads", "3"])
    if ran is None:
        return
    point = ran[0]["points"][0]
    clients = sorted(thread["name"] for thread in point["threads"] if thread["name"].startswith("clients-"))
    check("default: client threads as many as --streamer-threads",
          point["client_threads"] == 3 and clients == ["clients-0", "clients-1", "clients-2"],
          f"client_threads {point['client_threads']}, threads {clients}")


def tick_slots_follow_the_vehicles_per_streamer_thread(bench):
    """Without --tick-slots, one ticker slot per 10 vehicles of a Streamer thread (1 to 10);
    --tick-slots N is kept as given."""
    for arguments, expected in ((["--loopback", "25", "--streamer-threads", "1"], 3),
                                (["--loopback", "25", "--streamer-threads", "1", "--tick-slots", "7"], 7)):
        ran = run_fleet(bench, arguments + ["--virtual", "0", "--client-threads", "1"])
        if ran is None:
            continue
        point = ran[0]["points"][0]
        check(f"{' '.join(arguments)}: {expected} tick slots", point["tick_slots"] == expected and point["ok"],
              f"tick_slots {point['tick_slots']}, ok {point['ok']}")


def main():
    bench = sys.argv[1]
    ran = run_fleet(bench, ["--loopback", "4", "--virtual", "2", "--streamer-threads", "2", "--client-threads", "3"])
    if ran is None:
        return
    report, result = ran
    loopback, virtual = report["points"]
    check("both points ok", loopback["ok"] and virtual["ok"], json.dumps(report))
    check("client_threads recorded", loopback["client_threads"] == 3, str(loopback["client_threads"]))

    threads = loopback["threads"]
    names = sorted(thread["name"] for thread in threads)
    expected = sorted(["player", "streamers-0", "streamers-1", "clients-0", "clients-1", "clients-2"])
    check("each thread of the loopback point once, by name", names == expected, f"expected {expected}, got {names}")
    for thread in threads:
        fields_ok = all(key in thread for key in
                        ("cpu_s", "cpu_per_wall_s", "waiting_s", "voluntary_switches", "involuntary_switches", "saturated"))
        check(f"{thread['name']}: every field", fields_ok, json.dumps(thread))
        if not fields_ok:
            continue
        # A thread runs on one core at a time: its CPU cannot exceed the wall time (5 % for the
        # few µs between reading the clocks and the threads).
        check(f"{thread['name']}: 0 < CPU ≤ one core", 0 < thread["cpu_s"] <= 1.05 * loopback["wall_s"] + 0.001,
              f"{thread['cpu_s']} s of CPU in a {loopback['wall_s']} s window")
        check(f"{thread['name']}: waiting ≥ 0 and switches ≥ 0",
              thread["waiting_s"] >= 0 and thread["voluntary_switches"] >= 0 and thread["involuntary_switches"] >= 0,
              json.dumps(thread))
    # Every thread that ran in the window is listed, so together they are the process's CPU.
    total = sum(thread.get("cpu_s", 0) for thread in threads)
    process = loopback["cpu_s"]
    check("the threads' CPU adds up to the process's", abs(total - process) <= 0.2 * process + 0.01,
          f"threads {total:.4f} s, process {process:.4f} s")
    check("the virtual point's one thread is named", [t["name"] for t in virtual["threads"]] == ["world"],
          json.dumps(virtual["threads"]))
    # Virtual time runs flat out: its one thread is runnable all the window, the saturated verdict.
    check("the virtual point's thread is saturated", all(t["saturated"] for t in virtual["threads"]),
          json.dumps(virtual["threads"]))

    for line in ("loopback N=4: each thread over the", "busiest: ", "clients-2", "streamers-1", "player"):
        check(f"text report has '{line}'", line in result.stdout, result.stdout)
    clients_on_streamer_threads(bench)
    client_threads_follow_streamer_threads(bench)
    tick_slots_follow_the_vehicles_per_streamer_thread(bench)


if __name__ == "__main__":
    main()
    sys.exit(1 if failures else 0)
