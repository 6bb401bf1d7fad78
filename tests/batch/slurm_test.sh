#!/usr/bin/env bash
# `photoncl batch slurm` end to end: a single-node Slurm cluster brought up by hand
# under a temp folder (scripts/slurm_cluster.sh: munged, slurmctld, slurmd, no systemd), a
# 4-shard job submitted through it (a job array plus a merge that depends on it), and the merged
# image checked bit for bit against the same job rendered as one shard on this machine and against
# `photoncl render` of the same passes. Every daemon it started is stopped by its pid, on success,
# failure or interruption.
#
#   tests/batch/slurm_test.sh PHOTONCL SOURCE_DIR
#
# Exit 77 (CTest: skipped) when Slurm or munge is missing, except under CI (CI set), which
# installs them (scripts/setup.sh): there a missing package fails the test.
set -euo pipefail

photoncl=$(realpath "$1")
source_dir=$(realpath "$2")

missing=()
for tool in munged slurmctld slurmd sbatch squeue sinfo scontrol scancel; do
  command -v "$tool" >/dev/null || missing+=("$tool")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ -n "${CI:-}" ]; then
    echo "FAIL: ${missing[*]} missing in CI (scripts/setup.sh installs slurm-wlm and munge)" >&2
    exit 1
  fi
  echo "SKIP: ${missing[*]} not installed (slurm-wlm, munge)" >&2
  exit 77
fi

started=$(date +%s.%N)
seconds_since() { python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.1f}')" "$1" "$(date +%s.%N)"; }

tmp=$(mktemp -d "${TMPDIR:-/tmp}/photoncl-slurm.XXXXXX")
chmod 755 "$tmp"  # munged wants every folder up to its socket open to all for execute
cluster="$tmp/cluster"
cleanup() {
  local status=$?
  "$source_dir/scripts/slurm_cluster.sh" stop "$cluster" || status=1
  rm -rf "$tmp"
  exit $status
}
trap cleanup EXIT
trap 'exit 130' INT TERM

show_logs() {
  for log in "$tmp"/jobs/*/*.slurm/*.log "$cluster"/log/slurm*.log; do
    [ -f "$log" ] || continue
    echo "---- $log" >&2
    tail -n 40 "$log" >&2
  done
}
fail() { echo "FAIL: $*" >&2; show_logs; exit 1; }

# A tiny job: the Cornell box at 32x24, 4 passes of few photons and gather rays. The folder
# names have spaces, so the scripts' quoting is exercised on a real cluster too.
write_job() {  # FILE OUTPUT SHARDS
  mkdir -p "$(dirname "$1")"
  cat > "$1" <<EOF
{
  "scene": "$source_dir/scenes/cornell-box.json",
  "output": "$2",
  "shards": $3,
  "method": "fg",
  "passes": 4,
  "width": 32,
  "height": 24,
  "seed": 7,
  "globalPhotons": 4000,
  "causticPhotons": 2000,
  "gatherRays": 8,
  "lightSamples": 4
}
EOF
}
single="$tmp/jobs/single run/job.json"
sharded="$tmp/jobs/slurm run/job.json"
write_job "$single" "out/cornell.exr" 1
write_job "$sharded" "out/cornell.exr" 4

# The reference: the whole job as one shard here, merged. It also compiles the kernels into the
# shared cache, so the array tasks do not each compile them.
"$photoncl" batch run "$single" --shard 0/1 >"$tmp/reference.log" 2>&1 \
  || fail "batch run --shard 0/1 of the reference job: $(tail -n 20 "$tmp/reference.log")"
"$photoncl" batch merge "$single" >>"$tmp/reference.log" 2>&1 \
  || fail "batch merge of the reference job: $(tail -n 20 "$tmp/reference.log")"
reference="$tmp/jobs/single run/out/cornell.exr"
[ -f "$reference" ] || fail "the reference merge wrote no $reference"
# And `photoncl render` of the same passes, which accumulates the same way (README, "Exact merges").
"$photoncl" render "$source_dir/scenes/cornell-box.json" --method fg --passes 4 --width 32 --height 24 --seed 7 \
  --global-photons 4000 --caustic-photons 2000 --gather-rays 8 --light-samples 4 -o "$tmp/render.exr" --no-png -q \
  >>"$tmp/reference.log" 2>&1 || fail "photoncl render of the job's settings: $(tail -n 20 "$tmp/reference.log")"
echo "[figure] slurm test: references (1 shard, render; kernels cached) after $(seconds_since "$started") s"

cluster_start=$(date +%s.%N)
"$source_dir/scripts/slurm_cluster.sh" start "$cluster" || fail "the cluster did not come up"
export SLURM_CONF="$cluster/etc/slurm.conf"
echo "[figure] slurm test: cluster up (munged, slurmctld, slurmd; node idle) in $(seconds_since "$cluster_start") s"

# The dry run prints both scripts and submits nothing.
dry=$("$photoncl" batch slurm "$sharded" --dry-run) || fail "batch slurm --dry-run"
grep -q -- '^#SBATCH --array=0-3$' <<<"$dry" || fail "dry run: no '#SBATCH --array=0-3' in: $dry"
grep -q -- '--dependency=afterok:JOBID' <<<"$dry" || fail "dry run: no afterok dependency in: $dry"
[ -z "$(squeue -h)" ] || fail "the dry run submitted jobs: $(squeue)"

submit_start=$(date +%s.%N)
# --mem left to the default: 1.5x `batch plan`'s host estimate.
answer=$("$photoncl" batch slurm "$sharded" --time 5) || fail "batch slurm: $answer"
echo "$answer"
shards_job=$(sed -n 's/^shards: job \([0-9]*\),.*/\1/p' <<<"$answer")
merge_job=$(sed -n 's/^merge: job \([0-9]*\),.*/\1/p' <<<"$answer")
[ -n "$shards_job" ] && [ -n "$merge_job" ] || fail "no job ids in the answer: $answer"
# The merge job waits on the whole array.
scontrol -o show job "$merge_job" | grep -q "Dependency=afterok:${shards_job}" \
  || [ "$(scontrol -o show job "$merge_job" | grep -o 'JobState=[A-Z]*')" = "JobState=COMPLETED" ] \
  || fail "merge job $merge_job does not depend on $shards_job: $(scontrol -o show job "$merge_job")"

# The state a job ends in (COMPLETED, FAILED, CANCELLED, ...), waiting up to 40 s.
final_state() {
  local state=""
  for _ in $(seq 1 200); do
    state=$(scontrol -o show job "$1" | grep -o 'JobState=[A-Z_]*' | cut -d= -f2)
    case $state in
      PENDING | RUNNING | CONFIGURING | COMPLETING | "") sleep 0.2 ;;
      *) break ;;
    esac
  done
  echo "$state"
}
state=$(final_state "$merge_job")
[ "$state" = COMPLETED ] || fail "merge job $merge_job ended $state: $(scontrol -o show job "$merge_job")"
echo "[figure] slurm test: 4 array tasks + merge done $(seconds_since "$submit_start") s after submission"

tasks=$(scontrol -o show job "$shards_job" | grep -c 'JobState=COMPLETED' || true)
[ "$tasks" -eq 4 ] || fail "expected 4 completed array tasks of job $shards_job, got $tasks: $(scontrol -o show job "$shards_job")"
for i in 0 1 2 3; do
  shard=$(printf '%s/jobs/slurm run/out/cornell.exr.shards/shard-%04d-of-0004.pcls' "$tmp" "$i")
  [ -f "$shard" ] || fail "array task $i wrote no $shard"
  [ -f "$tmp/jobs/slurm run/out/cornell.exr.slurm/shard-$i.log" ] || fail "no log of array task $i"
done

for script in shards.sbatch merge.sbatch; do
  [ -f "$tmp/jobs/slurm run/out/cornell.exr.slurm/$script" ] || fail "batch slurm left no $script beside the output"
done
merged="$tmp/jobs/slurm run/out/cornell.exr"
[ -f "$merged" ] || fail "the merge job wrote no $merged"
# Bit for bit: RMSE exactly 0 means every channel of every pixel is the same float.
"$photoncl" compare "$merged" "$reference" --max-rmse 0 || fail "the merged image differs from the job as one shard"
"$photoncl" compare "$merged" "$tmp/render.exr" --max-rmse 0 || fail "the merged image differs from photoncl render"
echo "[figure] slurm test: merged image of 4 Slurm shards identical to the job as one shard and to photoncl render (RMSE 0)"

# A failing shard (a device that does not exist): the merge never runs; afterok can no longer be
# met and --kill-on-invalid-dep cancels it rather than leaving it pending.
cp "$merged" "$tmp/merged-before.exr"
answer=$("$photoncl" batch slurm "$sharded" --device no-such-device --mem-mib 256 --log-dir "$tmp/failing logs" \
         --job-name failing) || fail "batch slurm (failing): $answer"
shards_job=$(sed -n 's/^shards: job \([0-9]*\),.*/\1/p' <<<"$answer")
merge_job=$(sed -n 's/^merge: job \([0-9]*\),.*/\1/p' <<<"$answer")
state=$(final_state "$merge_job")
[ "$state" = CANCELLED ] || fail "merge job $merge_job after failing shards: expected CANCELLED, got $state"
grep -q "no-such-device" "$tmp/failing logs/shard-0.log" || fail "the failing shard's log does not name the device"
cmp -s "$merged" "$tmp/merged-before.exr" || fail "the cancelled merge changed $merged"
failed=$(scontrol -o show job "$shards_job" | grep -c 'JobState=FAILED' || true)
[ "$failed" -eq 4 ] || fail "expected 4 failed array tasks of job $shards_job, got $failed"
echo "[figure] slurm test: failing shards: merge job cancelled (DependencyNeverSatisfied)"
echo "[figure] slurm test: total $(seconds_since "$started") s"
