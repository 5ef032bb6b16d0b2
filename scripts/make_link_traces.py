#!/usr/bin/env python3
"""Writes the Mahimahi delivery traces the scenario library uses (scenario/traces/*.trace).

Mahimahi's format: one line per 1500-byte delivery opportunity, holding the millisecond at
which it occurs; the trace loops with its last timestamp as period. Each trace here is a list
of (seconds, Mbit/s) segments; within a segment opportunities are spread evenly, so a 12 Mbit/s
segment has exactly one per millisecond. Deterministic (no randomness): rerunning it rewrites
the same files, and `--check` fails when a committed trace differs from what this script makes.

    python3 scripts/make_link_traces.py            # rewrite scenario/traces/
    python3 scripts/make_link_traces.py --check    # verify them (exit 1 when stale)
"""
import pathlib
import sys

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


def main():
    check = sys.argv[1:] == ["--check"]
    folder = pathlib.Path(__file__).resolve().parent.parent / "scenario" / "traces"
    stale = []
    for name, (_, segments) in TRACES.items():
        text = "".join(f"{ms}\n" for ms in opportunities(segments))
        path = folder / f"{name}.trace"
        if check:
            if not path.exists() or path.read_text() != text:
                stale.append(str(path))
        else:
            folder.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
            print(f"{path}: {text.count(chr(10))} opportunities")
    if stale:
        print("stale traces (run scripts/make_link_traces.py):", *stale, sep="\n  ")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
