#!/usr/bin/env python3
"""A client for the Nagle tests of virtual time (tests/vtime/nagle_process_test.cpp): connects,
and for every "g" it reads writes "AAAA" and "BBBBBB" — in two writes (split), two writes with
TCP_NODELAY (split-nodelay) or one write (whole); "q" ends it; any other byte it ignores.

    split_writer.py PORT split|split-nodelay|whole
"""
import argparse
import socket
import sys

arguments = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
arguments.add_argument("port", type=int, help="the test's port on 127.0.0.1")
arguments.add_argument("mode", choices=["split", "split-nodelay", "whole"])
unknown = [word for word in sys.argv[1:] if word.startswith("-") and word not in ("-h", "--help")]
if unknown:   # named before argparse's "arguments are required", which would hide it
    arguments.error(f"unknown option {unknown[0]}")
options = arguments.parse_args()
port, mode = options.port, options.mode
sock = socket.create_connection(("127.0.0.1", port))
if mode == "split-nodelay":
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
while True:
    data = sock.recv(1)
    if not data or data == b"q":
        break
    if data != b"g":
        continue
    if mode == "whole":
        sock.sendall(b"AAAABBBBBB")
    else:
        sock.sendall(b"AAAA")
        sock.sendall(b"BBBBBB")
sock.close()
