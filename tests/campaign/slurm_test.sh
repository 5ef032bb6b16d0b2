#!/usr/bin/env bash
# The Slurm path end to end (issue #21 item 5, ctest label `slurm`): a local single-node cluster
# (scripts/slurm-local), a 200-world campaign as a 4-task job array through `ocp_campaign slurm`,
# and its merged results byte for byte against one local `ocp_campaign run` of the same seeds.
# Exit 77 (ctest SKIP_RETURN_CODE) with the reason when Slurm cannot be had here: not root, or
# the packages missing and not installable, or the daemons not starting (their logs' last lines
# are printed). A cluster that is up but gives a wrong result is a failure.
# Usage: slurm_test.sh OCP_CAMPAIGN SLURM_LOCAL WORK_DIR
set -uo pipefail
campaign=$1 slurm_local=$2 work=$3
seed=21 worlds=200 profile=calm tasks=4
skip=77

now() { date +%s.%N; }
fail() { echo "FAIL: $*"; exit 1; }

was_up=0
"$slurm_local" status >/dev/null 2>&1 && was_up=1
if ! started=$("$slurm_local" start 2>&1); then
  echo "$started"
  for log in /var/log/slurm-local/slurmctld.log /var/log/slurm-local/slurmd.log; do
    [ -r "$log" ] && { echo "--- last lines of $log"; tail -n 5 "$log"; }
  done
  [ "$was_up" -eq 1 ] || "$slurm_local" stop >/dev/null 2>&1   # whatever half of it started
  echo "SKIP: no local Slurm cluster here (scripts/slurm-local start failed; see above)"
  exit "$skip"
fi
echo "$started"
# Leave the machine as it was: stop the cluster only if this test started it.
[ "$was_up" -eq 1 ] || trap '"$slurm_local" stop >/dev/null 2>&1' EXIT

rm -rf "$work" && mkdir -p "$work" || fail "cannot create $work"

t0=$(now)
"$campaign" run --seed "$seed" --worlds "$worlds" --profile "$profile" -j 2 -q --out "$work/local" >"$work/local.txt" 2>&1
local_code=$?
t1=$(now)
"$campaign" slurm --seed "$seed" --worlds "$worlds" --profile "$profile" --tasks "$tasks" -j 1 \
  --out "$work/slurm" --poll 0.2 --timeout 120 >"$work/slurm.txt" 2>&1
slurm_code=$?
t2=$(now)

cat "$work/slurm.txt"
case "$local_code" in 0|1) ;; *) cat "$work/local.txt"; fail "local run exited $local_code" ;; esac
[ "$slurm_code" -eq "$local_code" ] || fail "ocp_campaign slurm exited $slurm_code, the local run $local_code"
[ -f "$work/slurm/campaign.sbatch" ] || fail "no campaign.sbatch"
grep -q -- "--array=0-$((tasks - 1))" "$work/slurm/campaign.sbatch" || fail "the script has no --array=0-$((tasks - 1))"
for task in $(seq 0 $((tasks - 1))); do
  [ -f "$work/slurm/shard-$task/summary.json" ] || fail "task $task wrote no shard-$task/summary.json"
done
# summary.json, junit.xml and index.html have no time and no shard split in them
# (docs/campaigns.md, "Output"): merged shards must equal the one run byte for byte.
for file in summary.json junit.xml index.html; do
  cmp "$work/local/$file" "$work/slurm/$file" || fail "merged $file differs from the local run's"
done
grep -q "\"worlds\"" "$work/slurm/summary.json" || fail "summary.json has no worlds"

awk -v t0="$t0" -v t1="$t1" -v t2="$t2" -v tasks="$tasks" 'BEGIN {
  printf "local run -j 2: %.2f s; slurm %d-task array (submit to merge): %.2f s; ratio %.2f\n", t1 - t0, tasks, t2 - t1, (t2 - t1) / (t1 - t0) }'
echo "PASS: $worlds worlds, seed $seed, profile $profile: merged Slurm results equal the local run"
