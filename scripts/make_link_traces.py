#!/usr/bin/env python3
"""Writes the link traces and the link recording the scenario library uses (scenario/traces/).

Mahimahi's format: one line per 1500-byte delivery opportunity, holding the millisecond at
which it occurs; the trace loops with its last timestamp as period. Each trace here is a list
of (seconds, Mbit/s) segments; within a segment opportunities are spread evenly, so a 12 Mbit/s
segment has exactly one per millisecond. Deterministic (no randomness): rerunning it rewrites
the same files, and `--check` fails when a committed trace differs from what this script makes.

The link recording replayed_drive.link (docs/link-recording.md) is the link of a recorded run:
the script runs scenario/traces/replayed_drive.source.yaml with ocp_scenario and records its
link with `ocp_scenario extract-link`. Virtual time makes that deterministic too, so `--check`
verifies it as well; it needs the built tool (--ocp-scenario PATH, default build/bin/ocp_scenario).
A change to the simulator that changes that run makes the recording stale: rerun the script.

    python3 scripts/make_link_traces.py            # rewrite scenario/traces/
    python3 scripts/make_link_traces.py --check    # verify them (exit 1 when stale)
"""
import pathlib
import subprocess
import sys
import tempfile

RECORDING = "replayed_drive"   # scenario/traces/replayed_drive.source.yaml -> replayed_drive.link

PACKET_BITS = 1500 * 8

# name -> (what it is, [(duration s, capacity Mbit/s), ...])
TRACES = {
    "cellular_collapse": (
        "an LTE uplink that collapses: 24 Mbit/s, then 0.6 Mbit/s for 6 s, then 24 Mbit/s again",
        [(4, 24.0), (6, 0.6), (10, 24.0)],
    ),
    "tunnel": (
        "a tunnel: 24 Mbit/s, nothing at all for 4 s, then 24 Mbit/s again",
        [(5, 24.0), (4, 0.0), (11, 24.0)],
    ),
}


def opportunities(segments):
    """Millisecond timestamps, one per delivery opportunity, evenly spread per segment."""
    lines = []
    start_ms = 0
    for seconds, mbps in segments:
        length_ms = int(seconds * 1000)
        packets_per_ms = mbps * 1e6 / PACKET_BITS / 1000
        for ms in range(1, length_ms + 1):
            # Whole opportunities due by the end of this millisecond, minus those before it.
            count = int(packets_per_ms * ms + 1e-9) - int(packets_per_ms * (ms - 1) + 1e-9)
            lines.extend([start_ms + ms] * count)
        start_ms += length_ms
    if not lines or lines[-1] != start_ms:
        # The period is the last timestamp: the trace must end exactly at its length.
        raise SystemExit(f"the last segment must have an opportunity in its last millisecond ({start_ms})")
    return lines


def recording(folder, tool):
    """The source scenario's link, as `ocp_scenario extract-link` records it from its trace."""
    source = folder / f"{RECORDING}.source.yaml"
    if not pathlib.Path(tool).is_file():
        raise SystemExit(f"{tool} not found: build it (scripts/build release ocp_scenario) or pass --ocp-scenario PATH")
    with tempfile.TemporaryDirectory() as out:
        run = subprocess.run([tool, "run", str(source), "--out", out], capture_output=True, text=True)
        if run.returncode != 0:
            raise SystemExit(f"{source} failed (exit {run.returncode}):\n{run.stdout}{run.stderr}")
        trace = pathlib.Path(out) / f"{RECORDING}.source" / "trace.jsonl"
        # Named relative to the repository in the header, wherever the run was written.
        text = subprocess.run([tool, "extract-link", str(trace), "--vehicle", "truck-1"],
                              capture_output=True, text=True, check=True).stdout
        return text.replace(str(trace), f"scenario/traces/{RECORDING}.source.yaml's trace.jsonl")


def arguments():
    args = sys.argv[1:]
    check = "--check" in args
    root = pathlib.Path(__file__).resolve().parent.parent
    tool = str(root / "build" / "bin" / "ocp_scenario")
    if "--ocp-scenario" in args:
        tool = args[args.index("--ocp-scenario") + 1]
    unknown = [a for a in args if a not in ("--check", "--ocp-scenario", tool)]
    if unknown:
        raise SystemExit(f"usage: make_link_traces.py [--check] [--ocp-scenario PATH]; unknown: {unknown}")
    return check, root / "scenario" / "traces", tool


def main():
    check, folder, tool = arguments()
    stale = []
    files = {f"{name}.trace": "".join(f"{ms}\n" for ms in opportunities(segments))
             for name, (_, segments) in TRACES.items()}
    files[f"{RECORDING}.link"] = recording(folder, tool)
    for file_name, text in files.items():
        path = folder / file_name
        if check:
            if not path.exists() or path.read_text() != text:
                stale.append(str(path))
        else:
            folder.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
            print(f"{path}: {text.count(chr(10))} lines")
    if stale:
        print("stale traces (run scripts/make_link_traces.py):", *stale, sep="\n  ")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
