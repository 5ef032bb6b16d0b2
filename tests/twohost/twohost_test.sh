#!/usr/bin/env bash
# The two-host test (issue #22): streamer_sim and the reference vehicle_client in one network
# namespace, player_sim and an operator TCP client in another, joined by a veth pair; the com
# channel between them is UDP with HMAC-SHA256. It shows that
#   1. the latency loop closes (the operator client reads message_latency_roundtrip, no faults);
#   2. the veth down for 3 s raises the SPEC §6 faults on both sides (NoControlMessage at the
#      Streamer, NoFeedbackMessage at the Player) and they clear once it is back up;
#   3. a Player with a wrong key is refused (the log says the key does not match, no key is
#      printed) and nothing it sent gets in;
#   4. a restarted Player (a new process, a new port) is answered at its new address;
#   5. 100 000 junk datagrams at the com port leave the loop running, the Streamer's memory flat
#      (VmRSS growth < 8 MiB) and the log quiet (one line per episode);
#   6. the first Player's datagrams, captured on the vehicle network (dumpcap) and replayed from
#      the attacker's own socket, get nothing in (issue #36): after a Player restart, as a flood
#      during a live session (message rate and latency within 10 % of a control period just
#      before, in which the same attacker floods a port where nothing listens), after 10 newer
#      sessions, and after a Streamer restart with the same key file.
#      Each: no session established by them, no peer move, every one counted as dropped.
# Where namespaces are not permitted (`ip netns add` fails: not root, no CAP_SYS_ADMIN) the same
# steps run over loopback and the test says so on its first line; the outage is then made by
# stopping each process for 3 s (SIGSTOP), since a loopback link cannot be taken down.
#
# usage: twohost_test.sh STREAMER_SIM PLAYER_SIM VEHICLE_CLIENT EXAMPLES_DIR WORKDIR [--loopback]
# Bounds are generous (a loaded 2-core machine): every wait polls for up to 20 s.
set -uo pipefail
streamer_sim=$1 player_sim=$2 vehicle_client=$3 examples=$4 work=$5
force_loopback=${6:-}
here=$(cd "$(dirname "$0")" && pwd)
wait_s=20

rm -rf "$work" && mkdir -p "$work" || exit 1
# Under AddressSanitizer freed memory waits in a quarantine (256 MiB by default), which would
# read as growth in the flood's VmRSS check; a small one keeps that check meaningful there.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}quarantine_size_mb=4"
ns_a="ocp2h_a_$$" ns_b="ocp2h_b_$$" veth_a="o2ha$$" veth_b="o2hb$$"
pids=()
mode=netns

cleanup() {
  local pid
  for pid in "${pids[@]}"; do kill -CONT "$pid" 2>/dev/null; kill "$pid" 2>/dev/null; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null; done
  if [ "$mode" = netns ]; then
    ip netns del "$ns_a" 2>/dev/null
    ip netns del "$ns_b" 2>/dev/null
  fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

fail() {
  echo "FAILED: $*"
  local log
  for log in "$work"/*.log "$work"/events; do
    [ -f "$log" ] && { echo "---- last lines of $log"; tail -n 15 "$log"; }
  done
  exit 1
}

# wait_for WHAT COMMAND...: polls COMMAND every 0.2 s for up to $wait_s seconds.
wait_for() {
  local what=$1 deadline=$((SECONDS + wait_s))
  shift
  until "$@"; do
    [ "$SECONDS" -lt "$deadline" ] || fail "$what (not within $wait_s s)"
    sleep 0.2
  done
  echo "ok: $what"
}

# ---- the two hosts ----
make_namespaces() {
  ip netns add "$ns_a" 2>"$work/netns.err" || return 1
  ip netns add "$ns_b" 2>>"$work/netns.err" || return 1
  ip link add "$veth_a" type veth peer name "$veth_b" 2>>"$work/netns.err" || return 1
  ip link set "$veth_a" netns "$ns_a" && ip link set "$veth_b" netns "$ns_b" || return 1
  ip -n "$ns_a" addr add 10.213.0.1/30 dev "$veth_a" && ip -n "$ns_b" addr add 10.213.0.2/30 dev "$veth_b" || return 1
  ip -n "$ns_a" link set lo up && ip -n "$ns_b" link set lo up || return 1
  ip -n "$ns_a" link set "$veth_a" up && ip -n "$ns_b" link set "$veth_b" up || return 1
}
if [ "$force_loopback" != --loopback ] && make_namespaces; then
  host_a=10.213.0.1
  echo "twohost: two network namespaces ($ns_a: streamer_sim + vehicle_client at $host_a;" \
       "$ns_b: player_sim + operator client at 10.213.0.2), joined by veth $veth_a/$veth_b"
else
  ip netns del "$ns_a" 2>/dev/null; ip netns del "$ns_b" 2>/dev/null
  mode=loopback host_a=127.0.0.1
  echo "twohost: NOTE: network namespaces are not permitted here ($(head -c 200 "$work/netns.err" 2>/dev/null || echo forced))," \
       "so this runs OVER LOOPBACK, not over a veth pair: the outage is made by SIGSTOP, not by a link going down"
fi
# on NS COMMAND...: becomes COMMAND, run in namespace NS (exec, so `on NS … &` leaves the
# program's own pid in $!: the cleanup and the kills below reach the program itself).
on() {
  local ns=$1
  shift
  if [ "$mode" = netns ]; then exec ip netns exec "$ns" "$@"; else exec "$@"; fi
}

# port_in LOG PATTERN: the port a program logged it listens on ("… listening on ADDR:PORT …").
port_in() { sed -n "s/.*$2 [^ ]*:\([0-9][0-9]*\)\b.*/\1/p" "$1" | head -n 1; }
# count_above FILE PATTERN N: more than N lines of FILE match PATTERN.
count_above() { [ "$(count "$1" "$2")" -gt "$3" ]; }
operator_messages() { sed -n 's/messages=\([0-9]*\).*/\1/p' "$work/status" 2>/dev/null; }
messages_above() { [ "$(operator_messages)" -gt "$1" ]; }
has_port() { [ -n "$(port_in "$1" "$2")" ]; }
count() { grep -c -- "$2" "$1" 2>/dev/null || true; }
last_state() { tail -n 1 "$work/events" 2>/dev/null; }
loop_closed() { [ "$(last_state)" = "state latency=yes sender= receiver=" ]; }

head -c 32 /dev/urandom >"$work/key" && head -c 32 /dev/urandom >"$work/wrong.key" || exit 1
key_hex=$(od -An -tx1 "$work/key" | tr -d ' \n') wrong_hex=$(od -An -tx1 "$work/wrong.key" | tr -d ' \n')

# ---- host A: streamer_sim and the reference vehicle_client ----
on "$ns_a" "$streamer_sim" --vehicle truck --com-listen "$host_a:0" --com-allow-remote --com-key "$work/key" \
  --plugin-param tcp_port 0 >"$work/streamer.log" 2>&1 &
streamer_pid=$!; pids+=("$streamer_pid")
wait_for "streamer_sim listens" has_port "$work/streamer.log" 'vehicle API listening on'
wait_for "streamer_sim's com channel listens" has_port "$work/streamer.log" 'com channel: listening on UDP'
com_port=$(port_in "$work/streamer.log" 'com channel: listening on UDP')
vehicle_port=$(port_in "$work/streamer.log" 'vehicle API listening on')
on "$ns_a" "$vehicle_client" --no-status "127.0.0.1:$vehicle_port" >"$work/vehicle_client.log" 2>&1 &
pids+=($!)

# ---- host B: player_sim and the operator client ----
start_player() {   # start_player LOG: a player_sim with the good key, and an operator client on it
  on "$ns_b" "$player_sim" --no-webview --vehicle "truck=udp://$host_a:$com_port" --com-key "$work/key" \
    --plugin-param ocp_player_tcp_port 0 >"$work/$1" 2>&1 &
  player_pid=$!; pids+=("$player_pid")
  wait_for "player_sim ($1) listens" has_port "$work/$1" 'operator API listening on'
  on "$ns_b" python3 "$here/observing_operator.py" "$examples" "127.0.0.1:$(port_in "$work/$1" 'operator API listening on')" \
    "$work/events" "$work/status" 2>>"$work/operator.log" &
  operator_pid=$!; pids+=("$operator_pid")
}
# The attacker's recording of the first Player's datagrams (hello and data) to the Streamer.
capture_if=lo
[ "$mode" = netns ] && capture_if=$veth_b
(on "$ns_b" dumpcap -i "$capture_if" -f "udp dst port $com_port" -P -w "$work/player1.pcap" -a duration:30 \
  >"$work/dumpcap.log" 2>&1) &
capture_pid=$!; pids+=("$capture_pid")
wait_for "dumpcap captures the com channel" grep -q "Capturing on" "$work/dumpcap.log"
start_player player.log

# 1. The latency loop closes across the network.
wait_for "the latency loop closes (operator client: message_latency_roundtrip, no faults)" loop_closed
wait_for "the Streamer measures the latency, no faults" grep -q "latency min/avg/max .* | faults none" "$work/streamer.log"
grep -q "com channel: the Player is at " "$work/streamer.log" || fail "the Streamer never learnt the Player's address"
sleep 1; kill -INT "$capture_pid" 2>/dev/null   # the recording: the first Player's handshake and 1 s+ of its session

# 2. The network is gone for 3 s: faults on both sides, cleared after.
no_control_before=$(count "$work/streamer.log" "fault raised: No Control Message")
cleared_before=$(count "$work/streamer.log" "fault cleared: No Control Message")
events_before=$(wc -l <"$work/events")
if [ "$mode" = netns ]; then
  ip -n "$ns_a" link set "$veth_a" down || fail "cannot take $veth_a down"
  sleep 3
  ip -n "$ns_a" link set "$veth_a" up || fail "cannot bring $veth_a up"
else
  kill -STOP "$player_pid"; sleep 3; kill -CONT "$player_pid"
  kill -STOP "$streamer_pid"; sleep 3; kill -CONT "$streamer_pid"
fi
wait_for "the Streamer raised NoControlMessage" \
  count_above "$work/streamer.log" "fault raised: No Control Message" "$no_control_before"
seen_since_outage() { tail -n "+$((events_before + 1))" "$work/events" | grep -q "$1"; }
wait_for "the Player raised NoFeedbackMessage (operator client's sender_fault)" seen_since_outage "sender=.*NoFeedbackMessage"
wait_for "the Streamer cleared NoControlMessage" \
  count_above "$work/streamer.log" "fault cleared: No Control Message" "$cleared_before"
wait_for "the loop closes again, every fault cleared on both sides" loop_closed

# 3. A Player with another key: refused, and nothing it sends gets in.
players_seen=$(count "$work/streamer.log" "com channel: the Player is at ")
on "$ns_b" "$player_sim" --no-webview --vehicle "truck=udp://$host_a:$com_port" --com-key "$work/wrong.key" \
  --plugin-param ocp_player_tcp_port 0 >"$work/wrong_player.log" 2>&1 &
wrong_pid=$!; pids+=("$wrong_pid")
wait_for "the Streamer says the key does not match" grep -q "key does not match" "$work/streamer.log"
# It keeps sending until it has printed two status lines: none of it may get in.
wait_for "the wrong-key Player ran 2 s" count_above "$work/wrong_player.log" "player_sim: status:" 1
kill "$wrong_pid"; wait "$wrong_pid" 2>/dev/null
[ "$(count "$work/streamer.log" "com channel: the Player is at ")" = "$players_seen" ] ||
  fail "the wrong-key Player's datagrams changed the Streamer's peer"
loop_closed || fail "the loop broke while the wrong-key Player was sending: $(last_state)"
if grep "player_sim: status:" "$work/wrong_player.log" | grep -vq "| in 0 msgs"; then
  fail "the wrong-key Player received messages from the Streamer"
fi
grep -q "bad MAC" "$work/streamer.log" && grep -Eq "dropped: [1-9][0-9]* bad MAC" "$work/streamer.log" ||
  fail "the Streamer's status line does not count the bad-MAC datagrams"
if grep -qiF -e "$key_hex" -e "$wrong_hex" "$work"/*.log; then fail "a key was printed in a log"; fi
echo "ok: the wrong key was refused; nothing it sent got in; no key in any log"

# 4. The Player restarts: a new process on a new port is answered there.
kill "$operator_pid" "$player_pid"; wait "$operator_pid" "$player_pid" 2>/dev/null
: >"$work/events"
start_player player2.log
wait_for "the Streamer answers the restarted Player at its new address" grep -q "com channel: the Player is at .*(was " "$work/streamer.log"
wait_for "the loop closes with the restarted Player" loop_closed

# 5. 100 000 junk datagrams at the com port.
rss_kib() { sed -n 's/^VmRSS:[^0-9]*\([0-9]*\).*/\1/p' "/proc/$streamer_pid/status"; }
rss_before=$(rss_kib)
junk_lines_before=$(count "$work/streamer.log" "com channel: dropped a datagram")
auth_lines_before=$(count "$work/streamer.log" "failed authentication: the key does not match")
summaries_before=$(count "$work/streamer.log" "com channel: invalid datagrams: ")
(on "$ns_b" python3 "$here/junk_flood.py" "$host_a" "$com_port" 100000) || fail "the flood did not run"
messages_after_flood=$(operator_messages)
wait_for "the operator client still gets feedback after the flood" messages_above "$((messages_after_flood + 50))"
wait_for "the loop is closed after the flood" loop_closed
rss_after=$(rss_kib)
growth=$((rss_after - rss_before))
echo "streamer_sim VmRSS: $rss_before KiB before the flood, $rss_after KiB after (growth $growth KiB)"
# Under AddressSanitizer (the sanitize stage) shadow memory and the quarantine above add to
# VmRSS whatever the program keeps: a looser bound there, said.
rss_bound=8192
if ldd "$streamer_sim" 2>/dev/null | grep -q libasan; then
  rss_bound=32768
  echo "note: an AddressSanitizer build: VmRSS bound $rss_bound KiB instead of 8192"
fi
[ "$growth" -lt "$rss_bound" ] || fail "the Streamer's memory grew by $growth KiB under the flood (bound $rss_bound KiB)"
junk_lines=$(( $(count "$work/streamer.log" "com channel: dropped a datagram") - junk_lines_before ))
auth_lines=$(( $(count "$work/streamer.log" "failed authentication: the key does not match") - auth_lines_before ))
[ "$junk_lines" -le 1 ] && [ "$auth_lines" -le 1 ] ||
  fail "the flood was logged $junk_lines + $auth_lines times, expected once per episode (and a summary)"
wait_for "the Streamer's log sums the flood up (once a period)" \
  count_above "$work/streamer.log" "com channel: invalid datagrams: " "$summaries_before"
echo "the flood in the Streamer's log: $((junk_lines + auth_lines)) line(s) in full, then:" \
  "$(grep "com channel: invalid datagrams: " "$work/streamer.log" | tail -n 1 | sed 's/.*com channel: //')"
kill -0 "$streamer_pid" 2>/dev/null || fail "streamer_sim died"

# 6. Replays of the first Player's recorded session (issue #36).
wait "$capture_pid" 2>/dev/null
established() { count "$work/streamer.log" "established with the Player"; }
moved() { count "$work/streamer.log" "com channel: the Player is at "; }
# dropped_so_far: the Streamer's latest status line's count of bad-MAC datagrams.
dropped_so_far() { grep -o "dropped: [0-9]* bad MAC" "$work/streamer.log" | tail -n 1 | grep -o "[0-9][0-9]*"; }
# measure SECONDS: "messages_per_s mean_latency_ms" the operator client saw over about SECONDS:
# its own count over its own clock, and the mean latency of every message in between
# (observing_operator.py's status line: messages=N latency_ms=L at=T latency_sum=S latency_count=C).
measure() {
  local start end
  start=$(cat "$work/status")
  sleep "$1"
  end=$(cat "$work/status")
  awk -v start="$start" -v end="$end" '
    function value(line, name,    parts, i, pair) {
      split(line, parts, " ")
      for (i in parts) { split(parts[i], pair, "="); if (pair[1] == name) return pair[2] + 0 }
      return 0
    }
    BEGIN {
      seconds = value(end, "at") - value(start, "at")
      count = value(end, "latency_count") - value(start, "latency_count")
      printf "%.1f %.1f\n", (seconds > 0 ? (value(end, "messages") - value(start, "messages")) / seconds : 0),
                            (count > 0 ? (value(end, "latency_sum") - value(start, "latency_sum")) / count : 0)
    }'
}
# replay_once LABEL: one pass of the recording, paced; nothing may get in.
replay_once() {
  local before_established before_moved before_dropped after_dropped
  before_established=$(established) before_moved=$(moved) before_dropped=$(dropped_so_far)
  (on "$ns_b" python3 "$here/replay_attack.py" "$work/player1.pcap" "$com_port" "$host_a" "$com_port") >"$work/replay.out" ||
    fail "$1: the replay did not run: $(cat "$work/replay.out")"
  sleep 2.5   # two status lines: the drops are counted in them
  after_dropped=$(dropped_so_far)
  [ "$(established)" = "$before_established" ] || fail "$1: the replay established a session"
  [ "$(moved)" = "$before_moved" ] || fail "$1: the replay moved the Streamer's peer"
  loop_closed || fail "$1: the loop broke: $(last_state)"
  echo "ok: $1: $(cat "$work/replay.out" | sed 's/replay_attack: //'); 0 accepted (no session, no peer move)," \
       "bad-MAC drops $before_dropped -> $after_dropped"
}
[ -s "$work/player1.pcap" ] || fail "dumpcap recorded nothing"
replay_once "replay after a Player restart"

# flood_measured PORT LABEL: the recording sent at 5 500 datagrams/s for 6 s to PORT of host A,
# and the loop measured over 5 s of it (after 0.5 s) into $work/LABEL.measured.
flood_measured() {
  local flood_pid
  (on "$ns_b" python3 "$here/replay_attack.py" "$work/player1.pcap" "$com_port" "$host_a" "$1" --seconds 6 --rate 5500) \
    >"$work/$2.out" 2>&1 &
  flood_pid=$!; pids+=("$flood_pid")
  sleep 0.5
  measure 5 >"$work/$2.measured"
  wait "$flood_pid" || fail "the $2 flood did not run: $(cat "$work/$2.out")"
}
# The control period carries the same attacker, sending the same datagrams at the same rate to a
# port where nothing listens (9, discard): on these 2 cores the attacker's own CPU delays the
# simulator's threads too, which is the machine's load, not the Streamer letting a replay harm
# the loop. A CPU-starved Streamer (beside stress-ng, or CI's next stage) also reads the
# Player's datagrams behind the flood's in its one socket: one window in four read a mean
# latency of 97 ms against 73. So up to three tries: a flood that harms the loop does it every
# time, and nothing may get in on any try.
flood_ok=0
for ((try = 1; try <= 3 && !flood_ok; try++)); do
  flood_measured 9 sham_flood
  before_established=$(established) before_moved=$(moved)
  flood_measured "$com_port" replay_flood
  control=$(cat "$work/sham_flood.measured") during=$(cat "$work/replay_flood.measured")
  echo "operator client, messages/s and mean latency ms (try $try): control (the same flood to port 9)" \
       "$control, during the replay flood $during ($(cat "$work/replay_flood.out"))"
  [ "$(established)" = "$before_established" ] && [ "$(moved)" = "$before_moved" ] ||
    fail "the replay flood established a session or moved the peer"
  awk -v c="$control" -v d="$during" 'BEGIN { split(c, a, " "); split(d, b, " ");
    exit !(a[1] > 0 && a[2] > 0 && b[1] > 0 && b[1] >= 0.9 * a[1] && b[2] <= 1.1 * a[2] + 2) }' && flood_ok=1
done
[ "$flood_ok" = 1 ] ||
  fail "the replay flood harmed the loop in three tries: last control $control, during $during (messages/s, latency ms; 10 % allowed)"
echo "ok: a replay flood during a live session: nothing got in, the loop within 10 % of the control period"

sessions_before=$(established)
for ((i = 1; i <= 10; i++)); do   # ten newer sessions: the Player re-handshakes after 1 s of silence
  kill -STOP "$streamer_pid"; sleep 1.5; kill -CONT "$streamer_pid"
  wait_for "session $((sessions_before + i)) is established" count_above "$work/streamer.log" "established with the Player" \
    "$((sessions_before + i - 1))"
done
wait_for "the loop closes after ten new sessions" loop_closed
replay_once "replay after 10 newer sessions"

kill "$streamer_pid"; wait "$streamer_pid" 2>/dev/null
mv "$work/streamer.log" "$work/streamer1.log"
on "$ns_a" "$streamer_sim" --vehicle truck --com-listen "$host_a:$com_port" --com-allow-remote --com-key "$work/key" \
  --plugin-param tcp_port "$vehicle_port" >"$work/streamer.log" 2>&1 &
streamer_pid=$!; pids+=("$streamer_pid")
wait_for "the restarted streamer_sim listens" has_port "$work/streamer.log" 'com channel: listening on UDP'
wait_for "the Player starts a session with the restarted Streamer" grep -q "established with the Player" "$work/streamer.log"
wait_for "the loop closes with the restarted Streamer" loop_closed
replay_once "replay after a Streamer restart with the same key"

echo "twohost ($mode): 6 passed, 0 failed"
