#!/usr/bin/env python3
"""The Wireshark dissector (scripts/wireshark/ocp.lua) against a real capture (issue #22).

    wireshark_test.py STREAMER_SIM PLAYER_SIM VEHICLE_CLIENT EXAMPLES_DIR OCP_LUA WORKDIR

A short loopback run (streamer_sim --com-listen with a key, player_sim --vehicle NAME=udp://…,
the reference vehicle_client and examples/operator_client.py), captured on lo by dumpcap while
both simulators write --wire-log. tshark then dissects the capture twice: once finding every
protocol by heuristic (the ports are not the defaults), once by port preference with the
heuristics disabled. Each time, for each of the four TCP flows, the dissected frames (length
prefix, ack_time, ack_time_mac) must equal the wire log's frames of that flow, in order; every
reassembled video frame must be as long as its size_bytes, and every SEI pair and returned
pair on the com channel must be one the wire logs saw on TCP.
Exit 77 (skipped, with the reason) only when tshark or dumpcap is not installed.
"""
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

WAIT_S = 20


def fail(message):
    print(f"FAILED: {message}")
    sys.exit(1)


def wait_for(what, condition):
    deadline = time.monotonic() + WAIT_S
    while not condition():
        if time.monotonic() > deadline:
            fail(f"{what} (not within {WAIT_S} s)")
        time.sleep(0.2)
    print(f"ok: {what}")


def registered_ports():
    """The ports Wireshark's own dissectors claim: ours must be found by heuristic, not theirs."""
    listing = subprocess.run(["tshark", "-G", "decodes"], capture_output=True, text=True).stdout
    return {int(fields[1]) for fields in (line.split("\t") for line in listing.splitlines())
            if len(fields) >= 2 and fields[0] in ("tcp.port", "udp.port") and fields[1].isdigit()}


def free_ports(count, taken):
    ports = []
    while len(ports) < count:
        with socket.socket() as tcp, socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as udp:
            tcp.bind(("127.0.0.1", 0))
            port = tcp.getsockname()[1]
            try:
                udp.bind(("127.0.0.1", port))
            except OSError:
                continue
        if port not in taken and port not in ports and port not in (4000, 4001, 5000):
            ports.append(port)
    return ports


def run_and_capture(args, work, ports):
    vehicle_port, operator_port, com_port = ports
    capture = os.path.join(work, "ocp.pcapng")
    processes = []

    def start(command, log):
        processes.append(subprocess.Popen(command, stdout=open(os.path.join(work, log), "w"), stderr=subprocess.STDOUT))
        return processes[-1]

    dumpcap = start(["dumpcap", "-q", "-i", "lo", "-w", capture, "-f",
                     f"tcp port {vehicle_port} or tcp port {operator_port} or udp port {com_port}"], "dumpcap.log")
    try:
        wait_for("dumpcap captures on lo", lambda: os.path.exists(capture) and os.path.getsize(capture) > 0)
        time.sleep(0.5)   # the filter is attached before the file's header is written, but be sure
        with open(os.path.join(work, "key"), "wb") as key:
            key.write(os.urandom(32))
        key_file = os.path.join(work, "key")
        start([args.streamer_sim, "--plugin-param", "tcp_port", str(vehicle_port), "--com-listen",
               f"127.0.0.1:{com_port}", "--com-key", key_file, "--wire-log", os.path.join(work, "streamer.wire")],
              "streamer.log")
        start([args.player_sim, "--no-webview", "--vehicle", f"truck=udp://127.0.0.1:{com_port}", "--com-key", key_file,
               "--plugin-param", "ocp_player_tcp_port", str(operator_port), "--wire-log",
               os.path.join(work, "player.wire")], "player.log")
        start([args.vehicle_client, "--no-status", f"127.0.0.1:{vehicle_port}"], "vehicle_client.log")
        start([sys.executable, os.path.join(args.examples, "operator_client.py"), f"127.0.0.1:{operator_port}"],
              "operator_client.log")
        player_wire = os.path.join(work, "player.wire")
        wait_for("300 client frames reach the Player (the loop runs)",
                 lambda: os.path.exists(player_wire) and open(player_wire).read().count('"dir":"in"') >= 300)
    finally:
        for process in reversed(processes[1:]):   # the clients first, then the simulators
            process.send_signal(signal.SIGTERM)
            process.wait(timeout=WAIT_S)
        time.sleep(0.5)
        dumpcap.send_signal(signal.SIGTERM)
        dumpcap.wait(timeout=WAIT_S)
    return capture


def wire_log(path):
    frames = []
    with open(path) as log:
        for line in log:
            event = json.loads(line)
            if event.get("event") == "frame" and not event["drained"]:
                frames.append(event)
    return frames


def leaves(node, out):
    """Every (field, value) under a tshark JSON layer, whatever the nesting."""
    if isinstance(node, dict):
        for key, value in node.items():
            if isinstance(value, (dict, list)):
                leaves(value, out)
            else:
                out.append((key, value))
    elif isinstance(node, list):
        for item in node:
            leaves(item, out)
    return out


def as_list(value):
    return value if isinstance(value, list) else [value]


def dissect(args, capture, options):
    command = ["tshark", "-X", f"lua_script:{args.lua}", "-r", capture, "-T", "json", "--no-duplicate-keys",
               "-j", "tcp udp ocp_vehicle ocp_operator ocp_com", *options]   # -j: not the JSON dissector's trees
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"{' '.join(command)} exited {result.returncode}: {result.stderr[-2000:]}")
    lua_errors = [line for line in result.stderr.splitlines() if "Lua" in line and "rror" in line]
    if lua_errors:
        fail(f"the dissector raised Lua errors: {lua_errors[:3]}")
    return json.loads(result.stdout)


def dissected_flows(packets, ports):
    """{(proto, from_server): [(length, ack_time, ack_time_mac), …]} and the com channel's items."""
    vehicle_port, operator_port, _ = ports
    flows = {}
    com = []
    for packet in packets:
        layers = packet["_source"]["layers"]
        for proto, server_port in (("ocp_vehicle", vehicle_port), ("ocp_operator", operator_port)):
            for pdu in as_list(layers.get(proto, [])):
                fields = dict(leaves({k: v for k, v in pdu.items() if k != "json"}, []))
                from_server = int(as_list(layers["tcp"])[0]["tcp.srcport"]) == server_port
                flows.setdefault((proto, from_server), []).append(
                    (int(fields[f"{proto}.length"]), fields.get(f"{proto}.ack_time"), fields.get(f"{proto}.ack_time_mac")))
        for pdu in as_list(layers.get("ocp_com", [])):
            com.append(dict(leaves(pdu, [])))
    return flows, com


def compare_flow(name, dissected, logged):
    """Equal in order; a run cut by SIGTERM may leave up to 3 frames on one side only."""
    shared = min(len(dissected), len(logged))
    if shared < 100:
        fail(f"{name}: only {len(dissected)} dissected and {len(logged)} logged frames")
    for index in range(shared):
        if dissected[index] != logged[index]:
            fail(f"{name}: frame {index}: dissected {dissected[index]}, wire log {logged[index]}")
    if abs(len(dissected) - len(logged)) > 3:
        fail(f"{name}: {len(dissected)} dissected frames, {len(logged)} in the wire log")
    print(f"ok: {name}: {shared} frames, length prefix / ack_time / ack_time_mac equal to the wire log")


def check(packets, ports, streamer_frames, player_frames, label):
    flows, com = dissected_flows(packets, ports)
    pair = lambda frame: (str(frame["ack_time"]), str(frame["ack_time_mac"])) if "ack_time" in frame else (None, None)
    logged = {
        ("ocp_vehicle", True): [(f["len"], *pair(f)) for f in streamer_frames if f["dir"] == "out"],
        ("ocp_vehicle", False): [(f["len"], *pair(f)) for f in streamer_frames if f["dir"] == "in"],
        ("ocp_operator", True): [(f["len"], None, None) for f in player_frames if f["dir"] == "out"],
        ("ocp_operator", False): [(f["len"], None, None) for f in player_frames if f["dir"] == "in"],
    }
    for key, frames in logged.items():
        dissected = flows.get(key, [])
        if key[0] == "ocp_operator":
            dissected = [(length, None, None) for length, _, _ in dissected]
        compare_flow(f"{label}: {key[0]} {'server to client' if key[1] else 'client to server'}", dissected, frames)
    check_com(com, streamer_frames, player_frames, label)


def check_com(com, streamer_frames, player_frames, label):
    echoed = {(str(f["ack_time"]), str(f["ack_time_mac"])) for f in streamer_frames if f["dir"] == "in" and "ack_time" in f}
    returned = set()
    for f in player_frames:
        if f["dir"] == "in" and "payload" in f:
            for entry in json.loads(f["payload"]).get("client_user_data", {}).values():
                if "ack_time_returned" in entry:
                    returned.add((str(entry["ack_time_returned"]), str(entry["ack_time_mac_returned"])))
    videos = [item for item in com if "ocp_com.size_bytes" in item]
    reassembled = [item for item in videos if "ocp_com.reassembled_length" in item]
    if len(reassembled) < 30:
        fail(f"{label}: only {len(reassembled)} reassembled video frames")
    for item in reassembled:
        if item["ocp_com.reassembled_length"] != item["ocp_com.size_bytes"]:
            fail(f"{label}: a reassembled frame of {item['ocp_com.reassembled_length']} bytes says {item['ocp_com.size_bytes']}")
    sei = {(item["ocp_com.ack_time"], item["ocp_com.ack_time_mac"]) for item in videos if "ocp_com.ack_time" in item}
    controls = [item for item in com if item.get("ocp_com.kind") == "1" and "ocp_com.ack_time" in item]
    sent_back = {(item["ocp_com.ack_time"], item["ocp_com.ack_time_mac"]) for item in controls}
    if len(sei) < 10 or not sei <= echoed:
        fail(f"{label}: {len(sei)} SEI pairs, {len(sei - echoed)} of them never echoed by the vehicle client")
    # Until the operator client's first message locks the source, the Player echoes the SEI pair
    # itself (SPEC §4.3): every returned pair is the client's or, before that, a SEI pair.
    from_client = sent_back & returned
    if len(from_client) < 10 or not sent_back <= returned | sei:
        fail(f"{label}: {len(sent_back)} returned pairs, {len(from_client)} sent by the operator client, "
             f"{len(sent_back - returned - sei)} from nowhere")
    # The session handshake (issue #36): the Player's hello and the Streamer's welcome, each with
    # its nonces, before the messages.
    hellos = [item for item in com if item.get("ocp_com.kind") == "6" and "ocp_com.player_nonce" in item]
    welcomes = [item for item in com if item.get("ocp_com.kind") == "7" and "ocp_com.streamer_nonce" in item]
    if not hellos or not welcomes:
        fail(f"{label}: the dissector shows {len(hellos)} hellos and {len(welcomes)} welcomes (expected the handshake)")
    if {w["ocp_com.player_nonce"] for w in welcomes}.isdisjoint({h["ocp_com.player_nonce"] for h in hellos}):
        fail(f"{label}: no welcome answers a hello's nonce")
    print(f"ok: {label}: com channel: handshake shown ({len(hellos)} hello, {len(welcomes)} welcome)")
    print(f"ok: {label}: com channel: {len(reassembled)} video frames reassembled to their size, {len(sei)} SEI pairs "
          f"echoed by the vehicle, {len(from_client)} returned pairs sent by the operator client")


class Args:
    def __init__(self, argv):
        (self.streamer_sim, self.player_sim, self.vehicle_client, self.examples, self.lua, self.work) = argv


def main():
    if len(sys.argv) != 7:
        print(__doc__)
        return 2
    args = Args(sys.argv[1:])
    missing = [tool for tool in ("tshark", "dumpcap") if shutil.which(tool) is None]
    if missing:
        print(f"SKIPPED: {' and '.join(missing)} not installed (scripts/setup --test installs the tshark package)")
        return 77
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    ports = free_ports(3, registered_ports())
    print(f"ports: vehicle API {ports[0]}, operator API {ports[1]}, com channel {ports[2]} (not the defaults)")
    capture = run_and_capture(args, args.work, ports)
    streamer_frames = wire_log(os.path.join(args.work, "streamer.wire"))
    player_frames = wire_log(os.path.join(args.work, "player.wire"))
    check(dissect(args, capture, []), ports, streamer_frames, player_frames, "by heuristic")
    by_port = ["-o", f"ocp_vehicle.tcp_port:{ports[0]}", "-o", f"ocp_operator.tcp_port:{ports[1]}",
               "-o", f"ocp_com.udp_port:{ports[2]}", "--disable-heuristic", "ocp_vehicle_tcp",
               "--disable-heuristic", "ocp_operator_tcp", "--disable-heuristic", "ocp_com_udp"]
    check(dissect(args, capture, by_port), ports, streamer_frames, player_frames, "by port")
    print("wireshark dissector: 2 passed, 0 failed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
