#!/usr/bin/env bash
# The project's Slurm job under a real Slurm: starts munged, slurmctld and
# slurmd for a one-node cluster on localhost with a stock MpiDefault=none, and
# submits jobs/slurm/helix.sbatch as users do.
#  1. A 2-rank job of the small helix ends with the frame a direct 1-rank run
#     ends with, to 1e-9 of the bounding-box diagonal (the standard of
#     tests/mpi/test_rank_invariance.cpp).
#  2. A 2-rank job stopped mid-run with `scancel --signal=USR1 --batch` (what
#     --signal=B:USR1@120 sends before the time limit) requeues itself, the
#     requeued job continues with --restart, and its frames are bitwise those
#     of an uninterrupted 2-rank run.
#  3. jobs/slurm/scaling_study.sh submits a weak-scaling array (1 and 2 ranks)
#     and a job that waits for all of it, requeued elements included, and
#     writes one table and plot (tools/scaling_table.py) of both elements.
# SKIPs (exit 0) where Slurm cannot run here: not root, or no Slurm or munge.
#   tests/slurm/slurm_job_test.sh BUILD_DIR
set -euo pipefail
skip() {
  echo "slurm_job_test: SKIP: $*"
  exit 0
}
fail() {
  echo "slurm_job_test: FAIL: $*" >&2
  exit 1
}

build=$(cd "${1:?usage: slurm_job_test.sh BUILD_DIR}" && pwd)
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=$build/src/app/descent
[ -x "$bin" ] || fail "no binary at $bin"
[ "$(id -u)" -eq 0 ] || skip "starting munged, slurmctld and slurmd needs root"
for command in munged slurmctld slurmd sbatch squeue scontrol scancel; do
  command -v "$command" >/dev/null || skip "no $command (Debian: apt-get install slurm-wlm munge)"
done
python=${PYTHON:-/usr/bin/python3}  # Debian's, where apt installs h5py and matplotlib
"$python" -c 'import h5py' 2>/dev/null || skip "no h5py for $python (Debian: python3-h5py)"
"$python" -c 'import matplotlib' 2>/dev/null || skip "no matplotlib for $python (Debian: python3-matplotlib)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1

tmp=$(mktemp -d -t descent-slurm.XXXXXX)
daemons=()
jobs=()
show_logs() {
  for log in "$tmp"/*.log; do
    echo "---- $log"
    tail -n 30 "$log"
  done
}
stop_daemons() {
  local status=$?
  [ "$status" -eq 0 ] || show_logs >&2
  [ ${#jobs[@]} -eq 0 ] || scancel "${jobs[@]}" 2>/dev/null || true
  # slurmd first, so no step outlives it; munged last, the others use it.
  local pid
  for ((i = ${#daemons[@]} - 1; i >= 0; --i)); do
    pid=${daemons[i]}
    kill "$pid" 2>/dev/null || continue
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
    kill -9 "$pid" 2>/dev/null || true
  done
  wait 2>/dev/null || true
  rm -rf "$tmp"
  exit "$status"
}
trap stop_daemons EXIT

# The cluster, all of it under $tmp: ports nobody listens on, its own munge
# socket and key, the node sized to this machine (at least 2 CPUs, so that 2
# ranks run where there is 1 core).
read -r ctld_port slurmd_port < <("$python" -c '
import socket
sockets = [socket.socket() for _ in range(2)]
for s in sockets: s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in sockets))')
cpus=$(($(nproc) > 2 ? $(nproc) : 2))
mkdir -p "$tmp/munge" "$tmp/state" "$tmp/spool" "$tmp/work"
chmod 700 "$tmp/munge"
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
export SLURM_CONF=$tmp/slurm.conf
cat >"$SLURM_CONF" <<EOF
ClusterName=descenttest
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
AuthType=auth/munge
CredType=cred/munge
# A requeued job waits cred_expire (default 120 s) before it may start again,
# and pending jobs wait for the scheduler's pass (default every 60 s).
AuthInfo=socket=$tmp/munge/munge.socket,cred_expire=10
SchedulerParameters=sched_interval=2
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/affinity
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
ReturnToService=2
MinJobAge=600
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
SlurmdParameters=config_overrides
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
EOF
munged --foreground --force --socket="$tmp/munge/munge.socket" --key-file="$tmp/munge/munge.key" \
  --log-file="$tmp/munged.log" --pid-file="$tmp/munge/munged.pid" \
  --seed-file="$tmp/munge/munged.seed" >"$tmp/munged.log" 2>&1 &
daemons+=($!)
for _ in $(seq 50); do [ -S "$tmp/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$tmp/munge/munge.socket" ] || skip "munged did not start (see above)"
slurmctld -D >"$tmp/slurmctld.out.log" 2>&1 &
daemons+=($!)
slurmd -D -N localhost >"$tmp/slurmd.out.log" 2>&1 &
daemons+=($!)
for _ in $(seq 100); do
  [ "$(sinfo -h -o %t 2>/dev/null)" = idle ] && break
  sleep 0.3
done
[ "$(sinfo -h -o %t 2>/dev/null)" = idle ] || skip "slurmctld and slurmd did not bring up a node"
echo "slurm_job_test: a one-node cluster on localhost ($cpus CPUs, MpiDefault=none)"

# Field $2 (e.g. JobState) of job $1 as scontrol shows it.
job_field() {
  scontrol show job "$1" 2>/dev/null | tr ' ' '\n' | sed -n "s/^$2=//p" | head -n 1
}
# Waits up to $2 seconds for job $1 to leave the queue for good; prints the
# final state. A requeued job passes through PENDING again on the way.
wait_job() {
  local state
  for _ in $(seq "$(($2 * 2))"); do
    state=$(job_field "$1" JobState)
    case $state in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY)
      echo "$state"
      return
      ;;
    esac
    sleep 0.5
  done
  echo "still ${state:-unknown} after $2 s"
}
# The job script as a user submits it: from a work directory outside the
# repository (hence DESCENT_ROOT), the small helix, options passed through.
submit() {
  local name=$1
  shift
  (cd "$tmp/work" && DESCENT_ROOT=$root DESCENT_BIN=$bin \
    DESCENT_SCENE=$root/jobs/study/small_helix.toml \
    sbatch --parsable --job-name="$name" --ntasks=2 --time=10 --output="$tmp/$name.log" \
    "$root/jobs/slurm/helix.sbatch" "$@")
}
# Compares the last frame of two frames.h5: "bitwise" or to 1e-9 of the
# bounding-box diagonal.
compare_frames() {
  "$python" - "$@" <<'EOF'
import sys
import h5py
import numpy as np

mode, files = sys.argv[1], sys.argv[2:]
last = []
for name in files:
    with h5py.File(name, "r") as f:
        frame = max(f["frames"], key=int)
        last.append((int(frame), f["frames"][frame]["positions"][...]))
(frame_a, a), (frame_b, b) = last
if frame_a != frame_b or a.shape != b.shape:
    sys.exit(f"last frames differ: {frame_a} {a.shape} against {frame_b} {b.shape}")
diagonal = np.linalg.norm(b.max(axis=0) - b.min(axis=0))
worst = np.abs(a - b).max()
equal = np.array_equal(a.view(np.uint64), b.view(np.uint64))
print(f"frame {frame_a}: {a.shape[0]} vertices, max difference {worst:.3g}"
      f" ({worst / diagonal:.3g} of the diagonal), bitwise {'equal' if equal else 'different'}")
ok = equal if mode == "bitwise" else worst <= 1e-9 * diagonal
sys.exit(0 if ok else 1)
EOF
}
scene=$root/jobs/study/small_helix.toml
out_of() { echo "$tmp/work/runs/$1-small_helix-np2"; }

# 1. The 2-rank job against a direct 1-rank run.
frames=6
"$bin" run "$scene" --set "time.frames=$frames" --out "$tmp/direct-np1" --quiet
job=$(submit short --set "time.frames=$frames")
jobs+=("$job")
state=$(wait_job "$job" 120)
[ "$state" = COMPLETED ] || fail "job $job: $state ($(job_field "$job" ExitCode))"
grep -q "via srun --mpi=pmix" "$tmp/short.log" || fail "job $job did not launch through srun --mpi=pmix"
compare_frames tolerance "$(out_of short)/frames.h5" "$tmp/direct-np1/frames.h5" ||
  fail "the 2-rank job's last frame is not the 1-rank run's"
echo "slurm_job_test: PASS: the 2-rank job ends where a direct 1-rank run does (${SECONDS} s)"

# 2. A job stopped mid-run requeues itself and ends bitwise where an
# uninterrupted run ends. Checkpoints only at the end, so that the one the
# requeued job continues from is the one the signal made.
frames=100
stop_set=(--set "time.frames=$frames" --set output.checkpoint_every=1000)
# Before the job, not alongside: ranks that outnumber the cores spin in MPI
# and slow each other down tenfold.
mpirun -n 2 --oversubscribe "$bin" run "$scene" "${stop_set[@]}" --out "$tmp/direct-np2" --quiet
job=$(submit stopped "${stop_set[@]}")
jobs+=("$job")
stats=$(out_of stopped)/stats.csv
for _ in $(seq 600); do
  [ -f "$stats" ] && [ "$(wc -l <"$stats")" -gt 3 ] && break
  sleep 0.2
done
if [ "$(job_field "$job" JobState)" != RUNNING ] || [ ! -f "$stats" ]; then
  fail "job $job was not running frames to stop"
fi
scancel --signal=USR1 --batch "$job"
echo "slurm_job_test: sent USR1 to job $job after frame $(($(wc -l <"$stats") - 1)) (${SECONDS} s)"
state=$(wait_job "$job" 180)
[ "$state" = COMPLETED ] || fail "job $job: $state ($(job_field "$job" ExitCode))"
restarts=$(job_field "$job" Restarts)
[ "${restarts:-0}" -ge 1 ] || fail "job $job completed without being requeued"
grep -q "restarting after frame" "$tmp/stopped.log" || fail "the requeued job did not --restart"
[ "$(wc -l <"$stats")" -eq $((frames + 1)) ] || fail "$stats has not one row per frame"
grep -E "^descent( job)?: .*(stopped|restart|requeued)" "$tmp/stopped.log"
compare_frames bitwise "$(out_of stopped)/frames.h5" "$tmp/direct-np2/frames.h5" ||
  fail "the requeued job's last frame is not the uninterrupted run's"
echo "slurm_job_test: PASS: the job stopped by USR1 requeued itself and ended bitwise where an uninterrupted run ends ($restarts requeue(s), ${SECONDS} s)"

# 3. A scaling study as jobs/slurm/scaling_study.sh submits it: a weak-scaling
# array over 1 and 2 ranks and a job that waits for the whole array
# (afterany) and writes one table and plot from both elements' stats.csv.
# The 2-rank element is stopped mid-run with USR1 and requeues itself: the
# table job must wait for the requeued element, not start when it first
# stops, and tabulate all its frames.
frames=100
study_log=$tmp/study.log
(cd "$tmp/work" && DESCENT_ROOT=$root DESCENT_BIN=$bin \
  "$root/jobs/slurm/scaling_study.sh" weak --array=1,2 --ntasks=2 --time=10 \
  --output="$tmp/study-%A_%a.log" -- 1.2 --set "time.frames=$frames" \
  --set output.checkpoint_every=1000) >"$study_log"
cat "$study_log"
read -r array table < <(sed -n 's/.*array job \([0-9]*\), table job \([0-9]*\).*/\1 \2/p' "$study_log")
if [ -z "$array" ] || [ -z "$table" ]; then fail "scaling_study.sh printed no job ids"; fi
jobs+=("$array" "$table")
[ "$(job_field "$table" Dependency)" != "(null)" ] || fail "table job $table has no dependency"
element=${array}_2
stats=$tmp/work/runs/descent-weak-r1.2-np2/stats.csv
for _ in $(seq 900); do
  [ -f "$stats" ] && [ "$(wc -l <"$stats")" -gt 3 ] && break
  sleep 0.2
done
[ "$(job_field "$element" JobState)" = RUNNING ] || fail "element $element was not running frames to stop"
[ "$(job_field "$table" JobState)" = PENDING ] || fail "table job $table did not wait for the array"
scancel --signal=USR1 --batch "$element"
echo "slurm_job_test: sent USR1 to element $element after frame $(($(wc -l <"$stats") - 1)) (${SECONDS} s)"
# While the element is requeued and runs again the table job must pend.
# The table's state is read first: the element ends before the table starts.
for _ in $(seq 900); do
  table_state=$(job_field "$table" JobState)
  state=$(job_field "$element" JobState)
  [ "$table_state" = PENDING ] || [ "$state" = COMPLETED ] ||
    fail "table job $table was $table_state while element $element was $state"
  [ "$state" = COMPLETED ] && break
  sleep 0.2
done
[ "$state" = COMPLETED ] || fail "element $element: $state ($(job_field "$element" ExitCode))"
[ "$(job_field "$element" Restarts)" -ge 1 ] || fail "element $element completed without being requeued"
state=$(wait_job "$table" 120)
[ "$state" = COMPLETED ] || fail "table job $table: $state ($(job_field "$table" ExitCode))"
study=$tmp/work/runs/scaling-weak-$array
for suffix in csv md png; do
  [ -s "$study.$suffix" ] || fail "the table job wrote no $study.$suffix"
done
"$python" - "$study.csv" "$frames" <<'PY' || fail "$study.csv is not the study's table"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert [int(r["ranks"]) for r in rows] == [1, 2], rows
assert all(int(r["frames"]) == int(sys.argv[2]) for r in rows), rows
assert float(rows[0]["efficiency"]) == 1.0 and float(rows[1]["efficiency"]) > 0, rows
print(f"table: ranks 1, 2; efficiency {float(rows[1]['efficiency']):.2f} at 2 ranks")
PY
echo "slurm_job_test: PASS: scaling_study.sh's table job waited for the array, requeued element included, and wrote one table and plot of both (${SECONDS} s)"
