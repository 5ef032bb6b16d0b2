#!/usr/bin/env python3
"""A client for the Nagle tests of virtual time (tests/vtime/nagle_process_test.cpp): connects,
and for every "g" it reads writes "AAAA" and "BBBBBB" — in two writes (split), two writes with
TCP_NODELAY (split-nodelay) or one write (whole); "q" ends it; any other byte it ignores.

    split_writer.py PORT split|split-nodelay|whole
"""
import socket
import sys

port, mode = int(sys.argv[1]), sys.argv[2]
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
