#!/usr/bin/env bash
# ctest: ocp_bench's exit codes (docs/usage.md, "Exit codes"): 2 when the run cannot be done
# (a busy port, a client that exits before it connects), 130 on Ctrl-C with the figures so far
# printed and written, marked interrupted.
# Usage: loop_exit_codes.sh OCP_BENCH VEHICLE_CLIENT OUT_DIR
set -u
bench=$1 client=$2 out=$3
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

# A busy port: another socket listens on it.
python3 -c 'import socket, sys, time
s = socket.socket(); s.bind(("127.0.0.1", 0)); s.listen()
print(s.getsockname()[1], flush=True); time.sleep(60)' > "$out/busy_port" &
holder=$!
trap 'kill $holder 2>/dev/null' EXIT
for _ in $(seq 100); do [ -s "$out/busy_port" ] && break; sleep 0.1; done
port=$(cat "$out/busy_port")
[ -n "$port" ] || fail "the port holder did not start"
"$bench" loop --quiet --port "$port" --duration-s 1 > "$out/busy.txt" 2>&1
code=$?
[ $code -eq 2 ] || fail "busy port: exit $code, expected 2: $(cat "$out/busy.txt")"
grep -q "cannot start the Streamer" "$out/busy.txt" || fail "busy port: no reason given: $(cat "$out/busy.txt")"

# A client that exits before it connects cannot be measured: a harness error.
"$bench" loop --quiet --duration-s 5 -- sh -c 'exit 3' > "$out/early.txt" 2>&1
code=$?
[ $code -eq 2 ] || fail "client exits early: exit $code, expected 2: $(cat "$out/early.txt")"
grep -q "before it connected" "$out/early.txt" || fail "client exits early: no reason: $(cat "$out/early.txt")"

# Ctrl-C 3 s into a 60 s run.
rm -f "$out/interrupted.json"
timeout --preserve-status -s INT 3 "$bench" loop --quiet --duration-s 60 --json "$out/interrupted.json" \
  -- "$client" '127.0.0.1:{port}' --no-status > "$out/interrupted.txt" 2>&1
code=$?
[ $code -eq 130 ] || fail "Ctrl-C: exit $code, expected 130: $(cat "$out/interrupted.txt")"
grep -q "^interrupted: " "$out/interrupted.txt" || fail "Ctrl-C: the table does not say interrupted: $(cat "$out/interrupted.txt")"
grep -q '"interrupted":true' "$out/interrupted.json" || fail "Ctrl-C: the JSON is not marked interrupted"
echo "ocp_bench exit codes: busy port 2, early client exit 2, Ctrl-C 130 — as documented"
