#!/usr/bin/env bash
# `ocp_campaign run --client` end to end (issues #21 and #34, ctest label `realtime`): worlds in
# real time (--time real; virtual time, the default, is tests/vtime/scripts/campaign_virtual_test.sh)
# against external vehicle clients.
#   * Good clients pass, with every client hazard drawn: the reference vehicle_client on the
#     world that once gave 4 false `conservation` violations (seed 2, world 0, 30 s: duplicates
#     and reordering on a monitor link), the Python and Node examples on 15 s default worlds.
#   * Each verdict can come out FAILED: a client that alters MACs fails client.echo; one that
#     rounds ack_time through a double fails client.echo in every world with a high offset;
#     one that exits after its first disconnect is caught in every 15 s world (client.reconnect
#     and client.alive); one that exits mid-world fails client.alive.
#   * A client that cannot be started, or exits before it connects, is exit 2 with the reason.
# Bounds are verdicts, not timings: nothing here depends on the machine's speed. The long runs go
# side by side in the background: they mostly wait on real time.
# Usage: client_test.sh OCP_CAMPAIGN VEHICLE_CLIENT WORK_DIR [EXAMPLES_DIR [NODE]]
# NODE: the node CMake found (tests/CMakeLists.txt, OCP_NODE); empty or absent: the Node example is skipped.
set -uo pipefail
campaign=$1 client=$2 work=$3 examples=${4:-} node=${5:-}
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }

# start NAME CLIENT_COMMAND [options]: a campaign in the background; its exit code goes to NAME.code.
start() {
  local name=$1 command=$2
  shift 2
  ( "$campaign" run --no-shrink -q --out "$work/$name" --client "$command" --time real "$@" >"$work/$name.out" 2>&1
    echo $? >"$work/$name.code" ) &
}
# finish NAME EXPECTED_EXIT: waits for it.
finish() {
  local name=$1 expected=$2
  while [ ! -s "$work/$name.code" ]; do sleep 0.2; done
  local code
  code=$(cat "$work/$name.code")
  [ "$code" -eq "$expected" ] || { cat "$work/$name.out"; fail "$name: exit $code, expected $expected"; }
  echo "ok: $name (exit $code)"
}
# run NAME EXPECTED_EXIT CLIENT_COMMAND [more options]: a 2-world calm campaign of 3 s worlds.
run() {
  local name=$1 expected=$2 command=$3
  shift 3
  start "$name" "$command" --profile calm --seed 4 --worlds 2 -j 2 --max-world-seconds 3 "$@"
  finish "$name" "$expected"
}
# summary_check NAME PYTHON: asserts on summary.json (loaded as `s`), printing it on failure.
summary_check() {
  python3 - "$work/$1/summary.json" "$2" <<'EOF' || { cat "$work/$1.out"; fail "$1: $2"; }
import json, sys
s = json.load(open(sys.argv[1]))
worlds = s["results"]
checks = lambda r: {v["check"] for v in r["violations"]}
assert eval(sys.argv[2]), json.dumps(worlds, indent=1)[:3000]
EOF
}

start regression "'$client' 127.0.0.1:{port} --no-status" --seed 2 --worlds 6 --world 0 --max-world-seconds 30
start no-reconnect "'$client' 127.0.0.1:{port} --no-status --no-reconnect" --seed 5 --worlds 4 -j 2 --max-world-seconds 15
if [ -n "$examples" ]; then
  start python "python3 '$examples/vehicle_client.py' 127.0.0.1:{port}" --seed 3 --worlds 2 -j 2 --max-world-seconds 15
  [ -n "$node" ] && start node "'$node' '$examples/vehicle_client.js' 127.0.0.1:{port}" --seed 6 --worlds 2 -j 2 \
    --max-world-seconds 15
fi

run good 0 "'$client' 127.0.0.1:{port} --no-status"
grep -q "\"worlds_run\": 2" "$work/good/summary.json" || fail "good: summary.json does not count 2 worlds"
grep -q "not judged in real time" "$work/good.out" || fail "good: the table shows unjudged checks as judged"

run corrupt-mac 1 "'$client' 127.0.0.1:{port} --no-status --misbehave-corrupt-mac"
grep -q 'client.echo' "$work/corrupt-mac.out" || { cat "$work/corrupt-mac.out"; fail "corrupt-mac: no client.echo"; }
ls "$work/corrupt-mac/failures/"world-*/world.yaml >/dev/null || fail "corrupt-mac: no world.yaml"
grep -q -- "--client" "$work/corrupt-mac/failures/"world-0/world.yaml || fail "corrupt-mac: the repro does not name the client"
grep -q "replay: ocp_campaign run .*--client" "$work/corrupt-mac.out" || { cat "$work/corrupt-mac.out"; fail "corrupt-mac: no replay line in the terminal"; }
grep -q 'report.html' "$work/corrupt-mac/index.html" && fail "corrupt-mac: index.html links a report.html no client world has"

run exits-early 1 "'$client' 127.0.0.1:{port} --no-status --duration-s 1"
grep -q 'client.alive' "$work/exits-early.out" || { cat "$work/exits-early.out"; fail "exits-early: no client.alive"; }

start double "'$client' 127.0.0.1:{port} --no-status --misbehave-ack-through-double" --profile calm --seed 4 --worlds 6 -j 2 --max-world-seconds 3
finish double 1
summary_check double "all('client.echo' in checks(r) for r in worlds if 'ack_time_above_2^53' in r['hazards']) and sum('ack_time_above_2^53' in r['hazards'] for r in worlds) >= 3"
grep -q 'rounded through a double' "$work/double.out" || { cat "$work/double.out"; fail "double: client.echo does not name the cause"; }

run missing 2 "/nonexistent/vehicle-client {port}"
grep -q "cannot run '/nonexistent/vehicle-client'" "$work/missing.out" || { cat "$work/missing.out"; fail "missing: no reason"; }

run exits-at-once 2 "echo 'no such server' >&2; exit 3"
grep -q 'exited with code 3 before it connected' "$work/exits-at-once.out" || { cat "$work/exits-at-once.out"; fail "exits-at-once: no reason"; }
grep -q 'no such server' "$work/exits-at-once.out" || fail "exits-at-once: the client's last lines are not shown"

finish no-reconnect 1
summary_check no-reconnect "len(worlds) == 4 and all({'client.reconnect', 'client.alive'} & checks(r) and 'streamer_close' in r['hazards'] for r in worlds)"
finish regression 0
if [ -n "$examples" ]; then
  finish python 0
  summary_check python "all('streamer_close' in r['hazards'] for r in worlds)"
  if [ -n "$node" ]; then finish node 0; fi
fi
wait
echo "PASS"
