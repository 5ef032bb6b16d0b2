#!/usr/bin/env bash
# `ocp_campaign run --client CMD --time virtual` end to end (issue #38, docs/virtual-time.md):
#   * the reference client passes two calm worlds with every client hazard, the whole oracle on;
#   * a client that corrupts the MAC FAILS (exit 1) in virtual time as in real time, and its
#     world is shrunk with the client: shrunk.yaml, whose repro line names the client and
#     --time virtual;
#   * a static binary cannot run in virtual time: exit 2, with the reason and the way out, also
#     without --time (virtual is the default with --client).
# Every campaign runs under `timeout` (a wall-clock watchdog beside the tool's own).
# Usage: campaign_virtual_test.sh OCP_CAMPAIGN VEHICLE_CLIENT STATIC_CLIENT WORK_DIR
set -uo pipefail
campaign=$1 client=$2 static_client=$3 work=$4
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }

# run NAME EXPECTED_EXIT CLIENT_COMMAND [more options]
run() {
  local name=$1 expected=$2 command=$3 code
  shift 3
  timeout 240 "$campaign" run -q --out "$work/$name" --client "$command" --time virtual --profile calm \
    --seed 4 --worlds 2 -j 2 --max-world-seconds 3 "$@" >"$work/$name.out" 2>&1
  code=$?
  [ "$code" -eq "$expected" ] || { cat "$work/$name.out"; fail "$name: exit $code, expected $expected"; }
  echo "ok: $name (exit $code)"
}

run reference 0 "$client --no-status 127.0.0.1:{port}" --no-shrink
run corrupt_mac 1 "$client --no-status --misbehave-corrupt-mac 127.0.0.1:{port}" --shrink-max 1
grep -q "client.echo\|InvalidMac\|fault_model" "$work/corrupt_mac/summary.json" || fail "corrupt_mac: no violation named in summary.json"
shrunk=$(ls "$work"/corrupt_mac/failures/world-*/shrunk.yaml 2>/dev/null | head -1)
[ -n "$shrunk" ] || fail "corrupt_mac: no shrunk.yaml"
grep -q "^# Reproduce: .*--client .*misbehave-corrupt-mac.*--time virtual" "$shrunk" || { head -5 "$shrunk"; fail "corrupt_mac: the repro line lacks the client or --time virtual"; }
run static 2 "$static_client" --no-shrink
grep -q "cannot run in virtual time" "$work/static.out" || { cat "$work/static.out"; fail "static: no reason given"; }
grep -q "use --time real" "$work/static.out" || fail "static: no way out given"
# Virtual is the default with --client: without --time the static binary is refused the same way.
timeout 60 "$campaign" run -q --out "$work/default" --client "$static_client" --profile calm --seed 4 --worlds 1 \
  --max-world-seconds 3 --no-shrink >"$work/default.out" 2>&1
code=$?
[ "$code" -eq 2 ] && grep -q "cannot run in virtual time" "$work/default.out" || { cat "$work/default.out"; fail "default: exit $code, not refused in virtual time"; }
echo "ok: --time defaults to virtual"
# Realistic worlds pass too, with the whole oracle: one-vehicle 60 s worlds of the benchmark
# profile, every client hazard drawn (user data from a plugin for a while among them: the
# plugin must go on returning the pair after it, or liveness fails every such world).
timeout 240 "$campaign" run -q --out "$work/long" --client "$client --no-status 127.0.0.1:{port}" \
  --profile bench-1v60s --seed 1 --worlds 4 -j 2 --no-shrink >"$work/long.out" 2>&1
code=$?
[ "$code" -eq 0 ] || { cat "$work/long.out"; fail "long: exit $code, expected 0"; }
grep -q '"user_data_over_8KiB"' "$work/long/summary.json" || fail "long: no world with the user-data hazard"
grep -q "✓  liveness" "$work/long.out" || { cat "$work/long.out"; fail "long: liveness not shown as judged"; }
grep -q '"client_time": "virtual"' "$work/long/summary.json" || fail "long: summary.json does not say virtual time"
echo "ok: 60 s worlds pass"
# The efficiency line counts the clients' CPU: each runs behind `/bin/sh -c`, killed with its
# group and reaped by init, so it is read from its process group, not from RUSAGE_CHILDREN.
children=$(sed -n 's/.*"children_cpu_seconds": \([0-9.]*\).*/\1/p' "$work/long/efficiency.json")
awk -v c="${children:-0}" 'BEGIN { exit !(c > 0.05) }' ||
  fail "long: efficiency.json counts ${children:-no} s of client CPU for four 60 s worlds of vehicle_client"
echo "ok: the clients' CPU is counted ($children s)"
echo "all virtual-time campaign checks passed"
