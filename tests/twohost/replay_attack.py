#!/usr/bin/env python3
"""Replays recorded com-channel datagrams from the attacker's own socket (issue #36).

    replay_attack.py CAPTURE.pcap DEST_PORT HOST PORT [--seconds S] [--rate N]

CAPTURE is a classic pcap (dumpcap -P) of a com channel; every UDP payload that went to
DEST_PORT (the Player's datagrams to the Streamer: hellos and data) is sent again, in order,
to HOST:PORT: once (no --seconds), or over and over for S seconds at about N datagrams a
second (a flood beside a live session). The attacker never has the key. Prints how many it
sent. Standard library only; bounded by S (or one pass).
"""
import argparse
import socket
import struct
import sys
import time


def udp_payloads(path, dest_port):
    """The payloads of the UDP datagrams to dest_port, in capture order (Ethernet, Linux cooked
    or raw IP link types; IPv4)."""
    with open(path, "rb") as f:
        data = f.read()
    magic = struct.unpack("<I", data[:4])[0]
    endian = "<" if magic in (0xA1B2C3D4, 0xA1B23C4D) else ">"
    link_type = struct.unpack(endian + "I", data[20:24])[0]
    at, out = 24, []
    while at + 16 <= len(data):
        _, _, captured, _ = struct.unpack(endian + "IIII", data[at:at + 16])
        packet = data[at + 16:at + 16 + captured]
        at += 16 + captured
        offset = {1: 14, 113: 16, 276: 20, 101: 0, 228: 0, 0: 4}.get(link_type)
        if offset is None or len(packet) < offset + 28:
            continue
        ip = packet[offset:]
        if ip[0] >> 4 != 4 or ip[9] != 17:
            continue
        header = (ip[0] & 15) * 4
        udp = ip[header:]
        if len(udp) < 8 or struct.unpack(">H", udp[2:4])[0] != dest_port:
            continue
        out.append(bytes(udp[8:struct.unpack(">H", udp[4:6])[0]]))
    return out


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("capture")
    parser.add_argument("dest_port", type=int)
    parser.add_argument("host")
    parser.add_argument("port", type=int)
    parser.add_argument("--seconds", type=float, default=0.0)
    parser.add_argument("--rate", type=float, default=5500.0)
    args = parser.parse_args()
    payloads = udp_payloads(args.capture, args.dest_port)
    if not payloads:
        print(f"replay_attack: no datagrams to port {args.dest_port} in {args.capture}")
        sys.exit(1)
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sent = 0
    start = time.monotonic()
    index = 0
    while True:
        if args.seconds <= 0 and index == len(payloads):
            break
        elapsed = time.monotonic() - start
        if args.seconds > 0 and elapsed >= args.seconds:
            break
        if args.seconds > 0 and sent > elapsed * args.rate:
            time.sleep(0.001)
            continue
        try:
            sock.sendto(payloads[index % len(payloads)], (args.host, args.port))
            sent += 1
        except OSError:
            time.sleep(0.001)
        index += 1
        if args.seconds <= 0 and sent % 50 == 0:
            time.sleep(0.001)   # one pass: paced, so the Streamer's socket buffer keeps every one
    print(f"replay_attack: sent {sent} recorded datagrams ({len(payloads)} distinct) to {args.host}:{args.port}")


if __name__ == "__main__":
    main()
