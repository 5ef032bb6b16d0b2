#!/usr/bin/env python3
"""Sends COUNT junk datagrams to HOST:PORT as fast as the socket takes them, then exits.

    junk_flood.py HOST PORT COUNT

Random lengths 0..1299 (some above the 1 200-byte limit) and random bytes; every third one
starts like a com datagram (magic "OC", version 2, a valid kind) so it gets past the first
checks and is refused by the tag. Bounded: COUNT datagrams, at most 60 s.
"""
import random
import socket
import sys
import time


def main():
    host, port, count = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    generator = random.Random(7)
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    deadline = time.monotonic() + 60
    sent = 0
    while sent < count and time.monotonic() < deadline:
        junk = bytearray(generator.randbytes(generator.randrange(1300)))
        if sent % 3 == 0 and len(junk) >= 4:
            junk[0:4] = b"OC\x02" + bytes([generator.randrange(1, 6)])
        try:
            sock.sendto(junk, (host, port))
        except OSError:
            time.sleep(0.001)         # a full socket buffer: the datagram is lost, as on a network
        sent += 1
    print(f"junk_flood: sent {sent} datagrams to {host}:{port}")


if __name__ == "__main__":
    main()
