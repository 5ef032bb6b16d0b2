#!/usr/bin/env bash
# `ocp_scenario run FILE -- CMD` (scenario/app/launched_clients.hpp): the tool launches the
# external clients itself, in both times.
#   * virtual time (the default): the reference client, and the Python examples as vehicle and
#     operator (--operator-client) clients, pass; a static binary is refused (exit 2, the reason
#     and the way out); a busy loop is found out (exit 2);
#   * real time: the clock starts at the client's connection (VehicleNoResponse clears within
#     200 ms of the start, although the client took longer to start); with --operator-client
#     the Python operator example runs on the Player's :4001 API, and the clock waits for it too
#     (it starts 3 s late, and locks the tcp source within 2 s of the start);
#   * a client that exits before it connects is exit 2 with its last lines, in both times; one
#     that never connects is a FAILED client verdict (virtual: its sleep is virtual too) or exit 2
#     after --connect-timeout-s (real); one that exits during the world fails its verdict. The
#     same for the operator client in real time;
#   * contradictory options are exit 2.
# Every run is under `timeout` (a wall-clock bound beside the tool's own watchdog).
# Usage: launch_test.sh OCP_SCENARIO VEHICLE_CLIENT STATIC_CLIENT EXAMPLES_DIR WORK_DIR
set -uo pipefail
tool=$1 client=$2 static_client=$3 examples=$4 work=$5
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }

cat >"$work/ext.yaml" <<'YAML'
seed: 7
duration: 5s
world:
  gamepad: drive
  vehicles:
    - name: truck-1
      in_process_client: false
      link: {delay: 10ms}
expect:
  faults:
    - {fault: VehicleNoResponse, cleared: {after: 0s, within: 200ms}}
    - {fault: NoControlMessage, never: true}
YAML
cat >"$work/operator.yaml" <<'YAML'
seed: 7
duration: 4s
world:
  gamepad: drive
  vehicles:
    - name: truck-1
      in_process_client: false
expect:
  faults:
    - {fault: VehicleNoResponse, cleared: {after: 0s, within: 2s}}
  events:
    - {event: source_locked, source: tcp, after: 0s, within: 2s}
YAML
cat >"$work/own_operator.yaml" <<'YAML'
seed: 7
duration: 1s
world:
  operator_client: {connect: true}
  vehicles:
    - name: truck-1
      in_process_client: false
expect:
  faults:
    - {fault: InvalidMac, never: true}
YAML
cat >"$work/internal.yaml" <<'YAML'
seed: 7
duration: 1s
world:
  vehicles:
    - name: truck-1
expect:
  faults:
    - {fault: InvalidMac, never: true}
YAML

# run NAME EXPECTED_EXIT [tool options…] -- CLIENT…   (the scenario: $scenario, ext.yaml unless set)
run() {
  local name=$1 expected=$2 code
  shift 2
  timeout 120 "$tool" run "$work/${scenario:-ext}.yaml" --out "$work/$name" "$@" >"$work/$name.out" 2>&1
  code=$?
  [ "$code" -eq "$expected" ] || { cat "$work/$name.out"; fail "$name: exit $code, expected $expected"; }
  echo "ok: $name (exit $code)"
}
says() { grep -q -- "$2" "$work/$1.out" || { cat "$work/$1.out"; fail "$1: does not say '$2'"; }; }

run reference 0 -- "$client" --no-status 127.0.0.1:{port}
says reference "the client (truck-1) connects and runs to the end of the world"
[ -f "$work/reference/ext/client-truck-1.log" ] || fail "reference: no client log"
run python 0 --operator-client "python3 '$examples/operator_client.py' 127.0.0.1:{port}" -- python3 "$examples/vehicle_client.py" 127.0.0.1:{port}
says python "the operator client connects and runs to the end of the world"
# The client starts 1 s late: with the clock started at the launch, VehicleNoResponse would clear
# after 1 s, not within 200 ms.
run real 0 --time real -- sh -c "sleep 1; exec '$client' --no-status 127.0.0.1:\$OCP_PORT"
says real "✓ VehicleNoResponse cleared within 200ms"

# The operator client in real time: it starts 3 s after the vehicle client, and the clock waits
# for it too. Started with the launch, the clock would see the tcp source locked after 3 s, not
# within 2 s; the Python vehicle example waits for the Streamer however long the wait.
operator_example="python3 '$examples/operator_client.py' 127.0.0.1:{port}"
vehicle_example=(python3 "$examples/vehicle_client.py" 127.0.0.1:{port})
scenario=operator run operator_real 0 --time real --operator-client "sleep 3; exec $operator_example" -- "${vehicle_example[@]}"
says operator_real "✓ the operator client connects and runs to the end of the world"
says operator_real "✓ source_locked tcp within"
grep -q "connected to 127.0.0.1" "$work/operator_real/operator/client-operator.log" || fail "operator_real: no operator client log"
scenario=operator run operator_exits_real 2 --time real --operator-client 'echo no module named ocp_operator >&2; exit 3' \
  -- "${vehicle_example[@]}"
says operator_exits_real "the operator client exited with code 3 before it connected"
says operator_exits_real "no module named ocp_operator"
scenario=operator run operator_never_real 2 --time real --connect-timeout-s 1 --operator-client 'exec sleep 600' \
  -- "${vehicle_example[@]}"
says operator_never_real "the Player's :4001 API within 1 s"
scenario=operator run operator_dies_real 1 --time real --operator-client "python3 -c \"import os, socket, time; \
s = socket.create_connection(('127.0.0.1', int(os.environ['OCP_PORT']))); time.sleep(1); os._exit(4)\"" -- "${vehicle_example[@]}"
says operator_dies_real "then exited with code 4 during the world"

run static 2 -- "$static_client"
says static "cannot run in virtual time"
says static "use --time real"
# At nice 19: its 3 s of CPU must not starve the real-time tests ctest runs beside this one.
run busy 2 -- nice -n 19 python3 -c "import os, socket; s = socket.create_connection(('127.0.0.1', int(os.environ['OCP_PORT'])))
while True: pass"
says busy "without ever waiting"

for time in virtual real; do
  run "exits_$time" 2 --time "$time" -- sh -c 'echo no module named ocp_client >&2; exit 3'
  says "exits_$time" "the client (truck-1) exited with code 3 before it connected"
  says "exits_$time" "no module named ocp_client"
done
run never_virtual 1 -- sleep 600
says never_virtual "never connected"
run never_real 2 --time real --connect-timeout-s 1 -- sleep 600
says never_real "no client connected for truck-1 within 1 s"
run dies 1 -- python3 -c "import os, socket, time; s = socket.create_connection(('127.0.0.1', int(os.environ['OCP_PORT']))); time.sleep(1); os._exit(4)"
says dies "then exited with code 4 during the world"

# Contradictions and impossibilities: exit 2, each named.
usage() {
  local name=$1 text=$2 code
  shift 2
  timeout 30 "$tool" run "$@" >"$work/$name.out" 2>&1
  code=$?
  [ "$code" -eq 2 ] || { cat "$work/$name.out"; fail "$name: exit $code, expected 2"; }
  says "$name" "$text"
  echo "ok: $name (exit 2)"
}
usage no_vehicle "has none" "$work/internal.yaml" --out "$work/u1" -- "$client" 127.0.0.1:{port}
usage no_command "give its client as -- CMD" "$work/ext.yaml" --out "$work/u2" --operator-client "true {port}"
usage empty_command "needs the client's command" "$work/ext.yaml" --out "$work/u3" --
usage own_operator "has its own operator client" "$work/own_operator.yaml" --out "$work/u4" --time real --operator-client "true {port}" -- true
usage both_clocks "contradict" "$work/ext.yaml" --out "$work/u5" --realtime --time virtual -- true
usage bad_time "--time" "$work/ext.yaml" --out "$work/u6" --time warp -- true
echo "all ocp_scenario launch checks passed"
