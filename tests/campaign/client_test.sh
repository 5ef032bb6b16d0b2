#!/usr/bin/env bash
# `ocp_campaign run --client` end to end (issue #21 item 4, ctest label `realtime`): short
# calm worlds in real time against the reference vehicle_client, two at a time. A good client
# passes; a client that alters MACs fails client.echo; one that exits mid-world fails
# client.alive; a client that cannot be started, or exits before it connects, is exit 2 with
# the reason. Bounds are verdicts, not timings: nothing here depends on the machine's speed.
# Usage: client_test.sh OCP_CAMPAIGN VEHICLE_CLIENT WORK_DIR
set -uo pipefail
campaign=$1 client=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }

# run NAME EXPECTED_EXIT CLIENT_COMMAND [more options]: runs a 2-world calm campaign.
run() {
  local name=$1 expected=$2 command=$3
  shift 3
  "$campaign" run --profile calm --seed 4 --worlds 2 -j 2 --max-world-seconds 3 --no-shrink -q \
    --out "$work/$name" --client "$command" "$@" >"$work/$name.out" 2>&1
  local code=$?
  [ "$code" -eq "$expected" ] || { cat "$work/$name.out"; fail "$name: exit $code, expected $expected"; }
  echo "ok: $name (exit $code)"
}

run good 0 "'$client' 127.0.0.1:{port} --no-status"
grep -q "\"worlds_run\": 2" "$work/good/summary.json" || fail "good: summary.json does not count 2 worlds"

run corrupt-mac 1 "'$client' 127.0.0.1:{port} --no-status --misbehave-corrupt-mac"
grep -q 'client.echo' "$work/corrupt-mac.out" || { cat "$work/corrupt-mac.out"; fail "corrupt-mac: no client.echo"; }
ls "$work/corrupt-mac/failures/"world-*/world.yaml >/dev/null || fail "corrupt-mac: no world.yaml"
grep -q -- "--client" "$work/corrupt-mac/failures/"world-0/world.yaml || fail "corrupt-mac: the repro does not name the client"

run exits-early 1 "'$client' 127.0.0.1:{port} --no-status --duration-s 1"
grep -q 'client.alive' "$work/exits-early.out" || { cat "$work/exits-early.out"; fail "exits-early: no client.alive"; }

run missing 2 "/nonexistent/vehicle-client {port}"
grep -q "cannot run '/nonexistent/vehicle-client'" "$work/missing.out" || { cat "$work/missing.out"; fail "missing: no reason"; }

run exits-at-once 2 "echo 'no such server' >&2; exit 3"
grep -q 'exited with code 3 before it connected' "$work/exits-at-once.out" || { cat "$work/exits-at-once.out"; fail "exits-at-once: no reason"; }
grep -q 'no such server' "$work/exits-at-once.out" || fail "exits-at-once: the client's last lines are not shown"
echo "PASS"
