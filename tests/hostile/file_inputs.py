#!/usr/bin/env python3
"""Every file input bounded in size and type (issue #36 item 3), through the built tools.

A table: every loader (scenario files, trace: and replay: files, extract-link's trace, campaign
profiles, checked scenarios and merged summaries, key files and gamepad recordings of both
simulators, conformance baselines) against every hostile input (a FIFO, /dev/zero,
/dev/urandom, a folder, a 2 GB sparse file, a missing file, /proc/self/environ). Each must end
with exit 2 within TIME_LIMIT_S, name the file and say why, print no line longer than
MAX_LINE, never echo the environment's secret, and stay under RSS_LIMIT_KIB. A YAML alias bomb in
user_data and expect.delivered, an over-long duration, a too-fast `every`, an overflowing
delay and a deeply nested line are checked the same way. Prints the numbers (time to exit 2,
peak RSS) per row; exit 0 when every row passed, 1 otherwise.

usage: file_inputs.py OCP_SCENARIO OCP_CAMPAIGN STREAMER_SIM PLAYER_SIM OCP_CONFORMANCE WORK_DIR
"""
import os
import resource
import shutil
import subprocess
import sys
import time

TIME_LIMIT_S = 10.0
MAX_LINE = 400
RSS_LIMIT_KIB = 400 * 1024
SECRET = "s3cr3t-never-printed"

scenario_tool, campaign_tool, streamer, player, conformance, work = map(os.path.abspath, sys.argv[1:7])
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def path(name):
    return os.path.join(work, name)


def write(name, text):
    with open(path(name), "w") as f:
        f.write(text)
    return path(name)


fifo = path("fifo")
os.mkfifo(fifo)
folder = path("folder")
os.mkdir(folder)
sparse = path("sparse")
with open(sparse, "wb") as f:
    f.truncate(2 << 30)   # 2 GB that take no disk

HOSTILE = {
    "fifo": fifo,
    "/dev/zero": "/dev/zero",
    "/dev/urandom": "/dev/urandom",
    "folder": folder,
    "2 GB file": sparse,
    "missing": path("no-such-file"),
    "/proc/self/environ": "/proc/self/environ",
}
EXPECT = {
    "fifo": "FIFO",
    "/dev/zero": "character device",
    "/dev/urandom": "character device",
    "folder": "folder",
    "2 GB file": "at most",
    "missing": "No such file",
    "/proc/self/environ": "",   # a regular file of no stated size: read under the cap, refused by its parser
}


def scenario_with_link(key, file):
    return write("link-%s.yaml" % key, "duration: 1s\nworld:\n  vehicles:\n    - name: a\n      to_player: {%s: %s}\n"
                 "expect:\n  thresholds: {latency_ms: ['count > 0']}\n" % (key, file))


# Each loader: a function from the hostile file to the command line that reads it.
LOADERS = {
    "scenario file": lambda f: [scenario_tool, "run", "--no-trace", "--out", path("out"), f],
    "trace: file": lambda f: [scenario_tool, "run", "--no-trace", "--out", path("out"), scenario_with_link("trace", f)],
    "replay: file": lambda f: [scenario_tool, "run", "--no-trace", "--out", path("out"), scenario_with_link("replay", f)],
    "extract-link trace": lambda f: [scenario_tool, "extract-link", f],
    "campaign profile": lambda f: [campaign_tool, "run", "--worlds", "1", "--out", path("campaign"), "--profile", f],
    "campaign check": lambda f: [campaign_tool, "check", f],
    "campaign merge": lambda f: [campaign_tool, "merge", f, "--out", path("merged")],
    "streamer key": lambda f: [streamer, "--plugin-param", "tcp_port", "0", "--com-listen", "127.0.0.1:0", "--com-key", f,
                               "--duration-s", "1"],
    "player key": lambda f: [player, "--plugin-param", "ocp_player_tcp_port", "0", "--no-webview",
                             "--vehicle", "a=udp://127.0.0.1:9", "--com-key", f, "--duration-s", "1"],
    "streamer gamepad": lambda f: [streamer, "--plugin-param", "tcp_port", "0", "--gamepad", f, "--duration-s", "1"],
    "player gamepad": lambda f: [player, "--plugin-param", "ocp_player_tcp_port", "0", "--no-webview", "--gamepad", f,
                                 "--duration-s", "1"],
    "conformance baseline": lambda f: [conformance, "vehicle", "--baseline", f],
    "streamer link trace": lambda f: [streamer, "--plugin-param", "tcp_port", "0", "--link-trace-up", f, "--duration-s", "1"],
}

failures = []
rows = []


def run(label, argv, expect_text):
    env = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "OCP_PADDING": "x" * 64, "OCP_SECRET": SECRET}
    start = time.monotonic()
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env, cwd=work)
    try:
        out, _ = proc.communicate(timeout=TIME_LIMIT_S)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, _ = proc.communicate()
        failures.append("%s: still running after %.0f s (expected exit 2)" % (label, TIME_LIMIT_S))
        return
    elapsed = time.monotonic() - start
    text = out.decode("utf-8", "replace")
    rows.append((label, proc.returncode, elapsed))
    problems = []
    if proc.returncode != 2:
        problems.append("exit %d, expected 2" % proc.returncode)
    if expect_text and expect_text not in text:
        problems.append("no '%s' in the output" % expect_text)
    if SECRET in text:
        problems.append("the output quotes the environment")
    longest = max((len(line) for line in text.splitlines()), default=0)
    if longest > MAX_LINE:
        problems.append("a line of %d characters (at most %d)" % (longest, MAX_LINE))
    if problems:
        failures.append("%s: %s\n    output: %s" % (label, "; ".join(problems), text[:600].replace("\n", "\n    ")))


for loader, command in LOADERS.items():
    for kind, file in HOSTILE.items():
        if kind == "/proc/self/environ" and loader in ("conformance baseline", "streamer key", "player key"):
            continue   # any text is a baseline, and any 16..1024 bytes a key: environ is a (strange) valid one
        if kind == "folder" and loader == "scenario file":
            continue   # `ocp_scenario run FOLDER` runs the folder's *.yaml files, by design
        run("%s ← %s" % (loader, kind), command(file), EXPECT[kind])

# The YAML itself: alias bombs (10^9 nodes in nine lines, as the user data of a client_data entry
# and as the user data an expect.delivered waits for), ceilings, overflow, deep nesting.
anchors = "".join("x%d: &x%d [%s]\n" % (i, i, ", ".join(["*x%d" % (i - 1)] * 10) if i else ", ".join(["z"] * 10))
                  for i in range(9))
expect = "expect:\n  thresholds: {latency_ms: ['count > 0']}\n"
base = "duration: 1s\nworld: {vehicles: [{name: a}]}\n"
YAML_ROWS = {
    "alias bomb in client_data user_data": (
        base + "timeline:\n  - at: 0s\n    client_data:\n      source: plugin\n      vehicles:\n        a:\n"
        "          user_data:\n" + "".join("            " + line + "\n" for line in anchors.splitlines()) + expect,
        "expands to more than"),
    "alias bomb in expect.delivered": (
        base + "expect:\n  delivered:\n    - vehicle: a\n      after: 0s\n      within: 1s\n      user_data:\n" +
        "".join("        " + line + "\n" for line in anchors.splitlines()), "expands to more than"),
    "over-long duration": (base.replace("1s", "100000h") + expect, "over the ceiling"),
    "overflowing delay": (base.replace("{name: a}", "{name: a, link: {delay: 9223372036854775807us}}") + expect,
                          "beyond the largest"),
    "exponent in a duration": (base.replace("1s", "1e308s") + expect, "without an exponent"),
    "client data every 1us": (base + "timeline:\n  - at: 0s\n    client_data: {source: plugin, every: 1us, vehicles: "
                              "{a: {user_data: 1}}}\n" + expect, "faster than the floor"),
    "deep nesting": ("duration: 1s\nworld: " + "[" * 100000 + "]" * 100000 + "\n", "nested deeper than"),
}
for label, (text, expect_text) in YAML_ROWS.items():
    run("scenario: " + label, [scenario_tool, "run", "--no-trace", "--out", path("out"),
                               write(label.replace(" ", "_").replace(".", "_") + ".yaml", text)], expect_text)

peak_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
slowest = max(rows, key=lambda row: row[2]) if rows else ("", 0, 0.0)
print("%d rows; slowest exit: %s in %.2f s; peak RSS of any tool %d MiB" % (len(rows), slowest[0], slowest[2],
                                                                           peak_kib // 1024))
if peak_kib > RSS_LIMIT_KIB:
    failures.append("peak RSS %d KiB, over %d KiB" % (peak_kib, RSS_LIMIT_KIB))
for failure in failures:
    print("✗ " + failure)
if failures:
    sys.exit(1)
print("✓ every loader refused every hostile input with exit 2, a reason, no leak and no hang")
