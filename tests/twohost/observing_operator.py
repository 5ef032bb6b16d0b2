#!/usr/bin/env python3
"""The operator client of the two-host test: examples/operator_client.py's protocol (it closes
the latency loop by returning every pair), plus a record of what it saw, for the test to poll.

    observing_operator.py EXAMPLES_DIR HOST:PORT EVENTS_FILE STATUS_FILE

EVENTS_FILE gets one line each time the view changes:
    state latency=yes|no sender=F1,F2 receiver=F3
(latency=yes: message_latency_roundtrip is a number). STATUS_FILE is rewritten (atomically) about
four times a second: "messages=N latency_ms=L at=T latency_sum=S latency_count=C", T the
client's monotonic clock when it counted N, S and C the sum and count of every latency it saw.
A window's rate and mean latency are then exact: N over the client's own interval (the poller's
0.25 s steps would make the rate ±10 % over 5 s), and S over C of every message in it (20
snapshots of a latency that moves 55–100 ms with the video frames would move the mean by ±10 ms). The client reconnects when the connection ends, and stops when
its parent test kills it.
"""
import json
import os
import select
import socket
import sys
import time

sys.path.insert(0, sys.argv[1])
from operator_client import Deframer, answer, frame  # noqa: E402  (the example's own code)


class Recorder:
    def __init__(self, events_path, status_path):
        self.events = open(events_path, "a", buffering=1)
        self.status_path = status_path
        self.view = None
        self.messages = 0
        self.latency = None
        self.latency_sum = 0      # over every message that had a latency, for a window's exact mean
        self.latency_count = 0
        self.status_written = 0.0

    def saw(self, shared):
        self.messages += 1
        entries = list(shared.get("vehicle_feedback", {}).values())
        if not entries:
            return
        entry = entries[0]
        self.latency = entry.get("message_latency_roundtrip")
        if isinstance(self.latency, int):
            self.latency_sum += self.latency
            self.latency_count += 1
        view = ("yes" if isinstance(self.latency, int) else "no",
                ",".join(sorted(entry.get("sender_fault") or [])),
                ",".join(sorted(entry.get("receiver_fault") or [])))
        if view != self.view:
            self.view = view
            self.events.write("state latency=%s sender=%s receiver=%s\n" % view)
        now = time.monotonic()
        if now - self.status_written >= 0.25:
            self.status_written = now
            temporary = self.status_path + ".tmp"
            with open(temporary, "w") as status:
                status.write("messages=%d latency_ms=%s at=%.6f latency_sum=%d latency_count=%d\n"
                             % (self.messages, self.latency, now, self.latency_sum, self.latency_count))
            os.replace(temporary, self.status_path)


def session(sock, recorder):
    deframer = Deframer()
    active = None
    last_sent = time.monotonic()
    while True:
        if select.select([sock], [], [], 0.5)[0]:
            data = sock.recv(65536)
            if not data:
                return
            for payload in deframer.feed(data):
                recorder.saw(json.loads(payload))
                reply, active = answer(json.loads(payload), active)
                if reply is not None:
                    sock.sendall(frame(reply))
                    last_sent = time.monotonic()
        if time.monotonic() - last_sent >= 0.5:
            sock.sendall(frame({}))
            last_sent = time.monotonic()


def main():
    host, _, port = sys.argv[2].rpartition(":")
    recorder = Recorder(sys.argv[3], sys.argv[4])
    while True:
        try:
            with socket.create_connection((host, int(port)), timeout=2) as sock:
                sock.settimeout(None)
                session(sock, recorder)
        except (OSError, ValueError, KeyError) as error:
            print(f"observing_operator: {error}; reconnecting", file=sys.stderr)
        time.sleep(0.2)


if __name__ == "__main__":
    main()
