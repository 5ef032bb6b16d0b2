#!/usr/bin/env python3
"""A minimal OCP operator client: Python 3 standard library only, written from docs/protocol.md.

It connects to the Player's operator API (default 127.0.0.1:4001), reads VehicleOcpShared and
answers with a ClientOcpShared that returns every control vehicle's latest ack_time/ack_time_mac
pair (as ack_time_returned/ack_time_mac_returned), selects a control vehicle as active_vehicle
and sends it a little user_data. When it has sent nothing for KEEP_ALIVE_PERIOD it sends the
keep-alive {}. It reconnects when the connection ends.

    python3 examples/operator_client.py [HOST:PORT]
    ocp_conformance operator -- python3 examples/operator_client.py 127.0.0.1:{port}
"""
import json
import select
import socket
import struct
import sys
import time

MAX_PAYLOAD = 16384        # bytes; a longer frame is read and skipped (protocol.md §2)
KEEP_ALIVE_PERIOD = 0.5    # s; the Player closes a connection after 2 s without a byte (§4.2)


def frame(message):
    payload = json.dumps(message, separators=(",", ":")).encode()
    return struct.pack("<I", len(payload)) + payload       # 4-byte little-endian length prefix


class Deframer:
    """Bytes in, whole payloads out: frames may arrive split or several in one read."""

    def __init__(self):
        self.buffer = b""
        self.skip = 0              # bytes of an oversized frame still to throw away

    def feed(self, data):
        self.buffer += data
        payloads = []
        while True:
            if self.skip:
                dropped = min(self.skip, len(self.buffer))
                self.buffer, self.skip = self.buffer[dropped:], self.skip - dropped
                if self.skip:
                    return payloads
            if len(self.buffer) < 4:
                return payloads
            (length,) = struct.unpack_from("<I", self.buffer)
            if length > MAX_PAYLOAD:
                print(f"warning: skipping an oversized frame of {length} bytes", file=sys.stderr)
                self.buffer, self.skip = self.buffer[4:], length
                continue
            if len(self.buffer) < 4 + length:
                return payloads
            payloads.append(self.buffer[4:4 + length])
            self.buffer = self.buffer[4 + length:]


def answer(shared, active):
    """The ClientOcpShared for the latest VehicleOcpShared, and the vehicle now active."""
    feedback = shared["vehicle_feedback"]
    control = sorted(name for name, entry in feedback.items() if not entry.get("is_monitor", False))
    if not control:
        return None, None              # monitors only: nothing to return, keep-alives suffice
    if active not in control:
        active = control[0]
    entries = {}
    for name in control:               # each entry is that vehicle's whole client state
        entries[name] = {
            "user_data": {"hello_from": "examples/operator_client.py"},
            "ack_time_returned": feedback[name]["ack_time"],        # unchanged, exact integers
            "ack_time_mac_returned": feedback[name]["ack_time_mac"],
        }
    return {"active_vehicle": active, "client_user_data": entries}, active


def session(sock):
    deframer = Deframer()
    active = None
    last_sent = time.monotonic()
    while True:
        wait = max(0.0, last_sent + KEEP_ALIVE_PERIOD - time.monotonic())
        if select.select([sock], [], [], wait)[0]:
            data = sock.recv(65536)
            if not data:
                return "closed by the Player"
            payloads = deframer.feed(data)
            if payloads:
                reply, active = answer(json.loads(payloads[-1]), active)   # the latest is enough
                if reply is not None:
                    sock.sendall(frame(reply))
                    last_sent = time.monotonic()
        if time.monotonic() - last_sent >= KEEP_ALIVE_PERIOD:
            sock.sendall(frame({}))    # keep-alive: resets the read timer, locks nothing
            last_sent = time.monotonic()


def main():
    host, _, port = (sys.argv[1] if len(sys.argv) > 1 else "127.0.0.1:4001").rpartition(":")
    backoff = 0.1
    while True:
        try:
            with socket.create_connection((host, int(port)), timeout=2) as sock:
                sock.settimeout(None)
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                print(f"connected to {host}:{port}", file=sys.stderr)
                backoff = 0.1
                reason = session(sock)
        except (OSError, ValueError, KeyError, TypeError) as error:
            reason = error
        print(f"disconnected ({reason}); reconnecting in {backoff:.1f} s", file=sys.stderr)
        time.sleep(backoff)
        backoff = min(backoff * 2, 2.0)


if __name__ == "__main__":
    try:
        main()
    except KeyboardInterrupt:
        pass
