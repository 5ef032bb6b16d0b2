#!/usr/bin/env python3
"""A minimal OCP vehicle client: Python 3 standard library only, written from docs/protocol.md.

It connects to the Streamer's vehicle API (default 127.0.0.1:4000), reads the control messages
and answers each one at once with its ack_time/ack_time_mac pair; when it has sent nothing for
RESPONSE_PERIOD it repeats the latest pair as a keep-alive. It reconnects when the connection
ends. Where a real vehicle would act on the controller, it only counts messages.

    python3 examples/vehicle_client.py [HOST:PORT]
    ocp_conformance vehicle -- python3 examples/vehicle_client.py 127.0.0.1:{port}
"""
import json
import select
import socket
import struct
import sys
import time

MAX_PAYLOAD = 16384        # bytes; a longer frame is read and skipped (protocol.md §2)
RESPONSE_PERIOD = 0.010    # s; keep-alive after this long without a response (§3.3, §8)


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


def session(sock):
    deframer = Deframer()
    pair = None                # no response before the first control message
    last_sent = time.monotonic()
    received = 0
    while True:
        wait = max(0.0, last_sent + RESPONSE_PERIOD - time.monotonic()) if pair else 1.0
        fresh = False
        if select.select([sock], [], [], wait)[0]:
            data = sock.recv(65536)
            if not data:
                return "closed by the Streamer"
            for payload in deframer.feed(data):
                message = json.loads(payload)      # Python ints are exact: a u64 stays a u64
                pair = (message["ack_time"], message["ack_time_mac"])
                received += 1
                fresh = True
                # A real vehicle applies message["controller"] (None when the operator disabled
                # the gamepad) here, behind its own watchdog and limits, without blocking.
        if pair and (fresh or time.monotonic() - last_sent >= RESPONSE_PERIOD):
            response = {
                "ack_time": pair[0],
                "ack_time_mac": pair[1],
                "vehicle_user_data": {"pos": None, "user_data": {"messages_received": received}},
            }
            sock.sendall(frame(response))
            last_sent = time.monotonic()


def main():
    host, _, port = (sys.argv[1] if len(sys.argv) > 1 else "127.0.0.1:4000").rpartition(":")
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
