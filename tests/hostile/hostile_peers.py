#!/usr/bin/env python3
"""Hostile peers against the simulators' three servers, as built (issue #19).

Starts streamer_sim (vehicle API, :4000) and player_sim (operator API, :4001, and the web view)
on free ports, then plays each hostile peer against them: garbage, huge length prefixes, deep
JSON nesting, never-reading peers, connection storms, slowloris and WebSocket garbage. After
each peer it checks that
  * the server's open fds and resident memory are back within a stated bound of the baseline,
  * a good client is served normally,
and at the end that no log line came more than once a second, counted over any 5 s (digits
ignored, so one line per connection of a storm counts as a repeat). Standard library only; every wait is bounded.
Exit 0 when every check passed, 1 otherwise (a ✗ line says which, expected against actual).

usage: hostile_peers.py STREAMER_SIM PLAYER_SIM [--only NAME]
"""
import argparse
import collections
import json
import os
import random
import re
import socket
import struct
import subprocess
import sys
import threading
import time

FD_SLACK = 4                 # fds above the baseline once a peer has left
RSS_SLACK_KIB = 24 * 1024    # resident memory above the baseline once a peer has left
SETTLE_S = 15.0              # how long resources may take to come back


class Server:
    """One simulator process, its log lines (time, text) and the ports it printed."""

    def __init__(self, argv, port_patterns):
        self.proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
        self.lines = []
        self.ports = {}
        self.patterns = port_patterns
        self.lock = threading.Lock()
        threading.Thread(target=self._read, daemon=True).start()
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and len(self.ports) < len(port_patterns):
            time.sleep(0.05)
        if len(self.ports) < len(port_patterns):
            self.stop()
            sys.exit(f"{argv[0]} did not print its ports: {self.lines[-5:]}")

    def _read(self):
        for line in self.proc.stdout:
            with self.lock:
                self.lines.append((time.monotonic(), line.rstrip("\n")))
            for name, pattern in self.patterns.items():
                found = re.search(pattern, line)
                if found and name not in self.ports:
                    self.ports[name] = int(found.group(1))

    def fds(self):
        return len(os.listdir(f"/proc/{self.proc.pid}/fd"))

    def rss_kib(self):
        with open(f"/proc/{self.proc.pid}/status") as status:
            for line in status:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
        return 0

    def stop(self):
        self.proc.terminate()
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()


def frame(obj):
    payload = json.dumps(obj).encode()
    return struct.pack("<I", len(payload)) + payload


def read_frames(sock, count, timeout):
    """Reads until `count` frames arrived or `timeout` passed; returns the decoded frames."""
    sock.settimeout(0.2)
    buffer, frames = b"", []
    deadline = time.monotonic() + timeout
    while len(frames) < count and time.monotonic() < deadline:
        try:
            data = sock.recv(65536)
        except socket.timeout:
            continue
        if not data:
            break
        buffer += data
        while len(buffer) >= 4:
            length = struct.unpack("<I", buffer[:4])[0]
            if len(buffer) < 4 + length:
                break
            frames.append(json.loads(buffer[4:4 + length]))
            buffer = buffer[4 + length:]
    return frames


def connect(port, timeout=5.0):
    return socket.create_connection(("127.0.0.1", port), timeout=timeout)


# ---- good clients ---------------------------------------------------------------------------

def good_vehicle(port):
    """A vehicle client that echoes: served when it gets 10 control frames in 5 s."""
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:   # the previous (hostile) vehicle may still be leaving
        with connect(port) as sock:
            frames = []
            for _ in range(10):
                got = read_frames(sock, 1, 1.0)
                if not got:
                    break
                frames += got
                msg = got[-1]
                sock.sendall(frame({"ack_time": msg["ack_time"], "ack_time_mac": msg["ack_time_mac"]}))
            if len(frames) >= 10:
                return True, f"{len(frames)} control frames echoed"
        time.sleep(0.2)
    return False, "no 10 control frames within 10 s"


def good_operator(port):
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        with connect(port) as sock:
            sock.sendall(frame({}))
            frames = read_frames(sock, 5, 3.0)
            if len(frames) >= 5:
                return True, f"{len(frames)} VehicleOcpShared frames"
        time.sleep(0.2)
    return False, "no 5 VehicleOcpShared frames within 10 s"


def http_get(port, path="/", origin=None, timeout=5.0):
    with connect(port, timeout) as sock:
        request = f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n"
        if origin:
            request += f"Origin: {origin}\r\n"
        sock.sendall((request + "\r\n").encode())
        sock.settimeout(timeout)
        reply = b""
        while b"\r\n" not in reply:
            data = sock.recv(4096)
            if not data:
                break
            reply += data
        return reply.split(b"\r\n", 1)[0].decode(errors="replace")


def good_webview(port):
    deadline = time.monotonic() + 10
    status = ""
    while time.monotonic() < deadline:
        try:
            status = http_get(port)
            if " 200 " in status:
                return True, status
        except OSError as error:
            status = str(error)
        time.sleep(0.2)
    return False, f"GET / gave {status!r}"


# ---- hostile peers --------------------------------------------------------------------------

def garbage(port, seconds=2.0, connections=20):
    rng = random.Random(7)
    end = time.monotonic() + seconds
    for _ in range(connections):
        if time.monotonic() > end:
            break
        try:
            with connect(port) as sock:
                sock.sendall(bytes(rng.getrandbits(8) for _ in range(4096)))
        except OSError:
            pass


def huge_prefix(port):
    """A prefix of 4 GiB - 1, then 1 MiB of filler: drained or closed, never buffered."""
    try:
        with connect(port) as sock:
            sock.sendall(struct.pack("<I", 0xFFFFFFFF))
            chunk = b"x" * 65536
            for _ in range(16):
                sock.sendall(chunk)
    except OSError:
        pass


def deep_nesting(port):
    payload = b"[" * 8000 + b"]" * 8000
    try:
        with connect(port) as sock:
            sock.sendall(struct.pack("<I", len(payload)) + payload)
            sock.settimeout(3)
            sock.recv(1)
    except OSError:
        pass


def never_read(port, seconds=3.0, connections=4):
    socks = []
    try:
        for _ in range(connections):
            sock = connect(port)
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
            sock.sendall(frame({}))
            socks.append(sock)
        time.sleep(seconds)
    except OSError:
        pass
    for sock in socks:
        sock.close()


def storm(port, count=300):
    for _ in range(count):
        try:
            sock = connect(port, 2)
            sock.close()
        except OSError:
            pass


def slowloris(port, connections=80, seconds=4.0):
    socks = []
    for _ in range(connections):
        try:
            sock = connect(port, 2)
            sock.sendall(f"GET / HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n".encode())
            socks.append(sock)
        except OSError:
            break
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        for sock in socks:
            try:
                sock.send(b"X-a: b\r\n")
            except OSError:
                pass
        time.sleep(0.5)
    # The good client must be served while the slow ones still hold their connections.
    result = good_webview(port)
    for sock in socks:
        sock.close()
    return result


def websocket_garbage(port):
    rng = random.Random(11)
    try:
        with connect(port) as sock:
            sock.sendall((f"GET /ws HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nOrigin: http://127.0.0.1:{port}\r\n"
                          "Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\n"
                          "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n").encode())
            sock.settimeout(3)
            sock.recv(4096)
            for _ in range(50):
                sock.sendall(bytes(rng.getrandbits(8) for _ in range(512)))
    except OSError:
        pass


# ---- the run --------------------------------------------------------------------------------

def settle(server, baseline_fds, baseline_rss):
    """The fds and RSS once back within bound in two reads in a row (0.2 s apart), or the last
    read at SETTLE_S. The reads that pass are the ones returned: a storm's last connections are
    still accepted from the listen backlog and closed for a while, so a later read may catch one
    of them in passing (it did, once, on a loaded machine: 14 fds a moment after 13)."""
    deadline = time.monotonic() + SETTLE_S
    in_bound = 0
    while True:
        fds, rss = server.fds(), server.rss_kib()
        in_bound = in_bound + 1 if fds <= baseline_fds + FD_SLACK and rss <= baseline_rss + RSS_SLACK_KIB else 0
        if in_bound >= 2 or time.monotonic() >= deadline:
            return fds, rss
        time.sleep(0.2)


FLOOD_WINDOW_S = 5.0   # a line may come once a second, counted over any 5 s: a short burst
                       # (a fault raised and cleared a few times before it is summarised as
                       # flapping) is no flood; one line per connection of a storm is


def repeated_lines(server):
    """Lines (digits ignored) said more than once a second over some 5 s, with their count."""
    with server.lock:
        lines = list(server.lines)
    times = collections.defaultdict(list)
    for at, text in lines:
        text = re.sub(r"^\[\s*[\d.]+\]\s*", "", text)
        times[re.sub(r"\d+", "#", text)].append(at)
    worst = {}
    for text, ats in times.items():
        start = 0
        for end in range(len(ats)):
            while ats[end] - ats[start] >= FLOOD_WINDOW_S:   # a window of 5 s, its end excluded
                start += 1
            count = end - start + 1
            if count > FLOOD_WINDOW_S + 1:   # + 1: a once-a-second line read with jitter
                worst[text] = max(worst.get(text, 0), count)
    return worst


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("streamer_sim")
    parser.add_argument("player_sim")
    parser.add_argument("--only", help="run only the peers whose name contains this")
    args = parser.parse_args()

    streamer = Server([args.streamer_sim, "--plugin-param", "tcp_port", "0", "--log-level", "info"],
                      {"vehicle": r"vehicle API listening on 127\.0\.0\.1:(\d+)"})
    player = Server([args.player_sim, "--plugin-param", "ocp_player_tcp_port", "0", "--webview-port", "0",
                     "--log-level", "info"],
                    {"operator": r"operator API listening on 127\.0\.0\.1:(\d+)",
                     "webview": r"web view on http://127\.0\.0\.1:(\d+)/"})
    vehicle, operator, webview = streamer.ports["vehicle"], player.ports["operator"], player.ports["webview"]
    time.sleep(1.0)
    results = []
    try:
        baseline = {id(streamer): (streamer.fds(), streamer.rss_kib()), id(player): (player.fds(), player.rss_kib())}
        print(f"baseline: streamer_sim {baseline[id(streamer)][0]} fds {baseline[id(streamer)][1]} KiB; "
              f"player_sim {baseline[id(player)][0]} fds {baseline[id(player)][1]} KiB", flush=True)
        plan = [
            ("vehicle garbage", streamer, lambda: garbage(vehicle), lambda: good_vehicle(vehicle)),
            ("vehicle huge prefix", streamer, lambda: huge_prefix(vehicle), lambda: good_vehicle(vehicle)),
            ("vehicle deep nesting", streamer, lambda: deep_nesting(vehicle), lambda: good_vehicle(vehicle)),
            ("vehicle never reads", streamer, lambda: never_read(vehicle, connections=1), lambda: good_vehicle(vehicle)),
            ("vehicle storm", streamer, lambda: storm(vehicle), lambda: good_vehicle(vehicle)),
            ("operator garbage", player, lambda: garbage(operator), lambda: good_operator(operator)),
            ("operator huge prefix", player, lambda: huge_prefix(operator), lambda: good_operator(operator)),
            ("operator deep nesting", player, lambda: deep_nesting(operator), lambda: good_operator(operator)),
            ("operator never reads", player, lambda: never_read(operator), lambda: good_operator(operator)),
            ("operator storm", player, lambda: storm(operator), lambda: good_operator(operator)),
            ("webview slowloris", player, lambda: slowloris(webview), lambda: good_webview(webview)),
            ("webview websocket garbage", player, lambda: websocket_garbage(webview), lambda: good_webview(webview)),
            ("webview storm", player, lambda: storm(webview), lambda: good_webview(webview)),
        ]
        for name, server, attack, good in plan:
            if args.only and args.only not in name:
                continue
            started = time.monotonic()
            during = attack()
            fds, rss = settle(server, *baseline[id(server)])
            served, how = good()
            base_fds, base_rss = baseline[id(server)]
            checks = [
                (fds <= base_fds + FD_SLACK, f"fds ≤ {base_fds + FD_SLACK}", f"{fds}"),
                (rss <= base_rss + RSS_SLACK_KIB, f"RSS ≤ {base_rss + RSS_SLACK_KIB} KiB", f"{rss} KiB"),
                (served, "a good client served", how),
            ]
            if isinstance(during, tuple):
                checks.append((during[0], "a good client served during the attack", during[1]))
            ok = all(c[0] for c in checks)
            results.append(ok)
            print(f"{'✓' if ok else '✗'} {name} ({time.monotonic() - started:.1f} s)", flush=True)
            for passed, expected, actual in checks:
                if not passed:
                    print(f"    expected {expected}, actual {actual}", flush=True)
        for server, label in ((streamer, "streamer_sim"), (player, "player_sim")):
            floods = repeated_lines(server)
            ok = not floods
            results.append(ok)
            print(f"{'✓' if ok else '✗'} {label}: no log line more than once a second", flush=True)
            for text, count in sorted(floods.items(), key=lambda item: -item[1])[:8]:
                print(f"    expected ≤ {FLOOD_WINDOW_S:g} in {FLOOD_WINDOW_S:g} s, actual {count}: {text[:160]}", flush=True)
    finally:
        streamer.stop()
        player.stop()
    passed = sum(results)
    print(f"{passed} passed, {len(results) - passed} failed")
    return 0 if passed == len(results) else 1


if __name__ == "__main__":
    sys.exit(main())
