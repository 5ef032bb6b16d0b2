#!/usr/bin/env python3
"""A vehicle client for the virtual-time tests: connects, and from then on writes one valid
response every PERIOD seconds and nothing else (no echo at once). With a period just over the
Streamer's 2 s read timeout it is closed; just under, it is not.

    keepalive_client.py PORT PERIOD_SECONDS
"""
import argparse
import json
import socket
import struct
import sys
import time

arguments = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
arguments.add_argument("port", type=int, help="the Streamer's port on 127.0.0.1")
arguments.add_argument("period", type=float, help="seconds between two responses")
unknown = [word for word in sys.argv[1:] if word.startswith("-") and word not in ("-h", "--help")]
if unknown:   # named before argparse's "arguments are required", which would hide it
    arguments.error(f"unknown option {unknown[0]}")
options = arguments.parse_args()
port, period = options.port, options.period
sock = socket.create_connection(("127.0.0.1", port))
sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
sock.setblocking(False)
buffer = b""
pair = (0, 0)
next_send = time.monotonic() + period
while True:
    time.sleep(max(0.0, next_send - time.monotonic()))
    try:
        while True:
            data = sock.recv(65536)
            if not data:
                sys.exit(0)
            buffer += data
    except BlockingIOError:
        pass
    while len(buffer) >= 4:
        (length,) = struct.unpack_from("<I", buffer)
        if len(buffer) < 4 + length:
            break
        message = json.loads(buffer[4:4 + length])
        buffer = buffer[4 + length:]
        pair = (message["ack_time"], message["ack_time_mac"])
    payload = json.dumps({"ack_time": pair[0], "ack_time_mac": pair[1], "vehicle_user_data": {"pos": None, "user_data": {}}}).encode()
    try:
        sock.sendall(struct.pack("<I", len(payload)) + payload)
    except OSError:
        sys.exit(0)
    next_send += period
