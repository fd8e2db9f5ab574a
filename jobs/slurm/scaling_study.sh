#!/usr/bin/env bash
# A whole scaling study in one command: submits the array job of
# jobs/slurm/strong_scaling.sbatch or weak_scaling.sbatch, and a job that
# starts once every element has ended (--dependency=afterany:ARRAYID) and
# writes one table and plot of time per step and efficiency from their
# stats.csv (jobs/slurm/scaling_table.sbatch, tools/scaling_table.py).
#
#   jobs/slurm/scaling_study.sh strong|weak [sbatch options...] [-- script arguments...]
#
#   jobs/slurm/scaling_study.sh strong --array=1,2,4,8,16 --ntasks=16 -- 316k
#   jobs/slurm/scaling_study.sh weak --array=1-64 --ntasks=64 -p compute -- 2.42 --set time.frames=20
#
# sbatch options go to the array job (defaults: the script's #SBATCH lines,
# --array=1,2,4,8 --ntasks=8); --partition/-p, --account/-A, --qos/-q,
# --reservation, --clusters/-M and --chdir/-D also to the table job, which
# must run where the array ran. Arguments after -- go to the array script
# (PRESET or RESOLUTION, then `descent run` options). Run it from the
# directory the runs should go to (runs/ there), in the repository or not:
# DESCENT_ROOT defaults to the repository this script is in and reaches the
# jobs through sbatch's environment, as DESCENT_BIN, DESCENT_SCENE do.
#
# Prints the two job ids and where the table will be: runs/scaling-MODE-ARRAYID
# .csv, .md and .png. afterany, not afterok: a study with a failed element
# still gets the table of the others, and the table job then fails, naming
# what is missing (its log: descent-scaling-table-JOBID.log). A requeued
# element (stopped at its time limit) is pending again, not ended, so the
# table waits for it.
set -euo pipefail
usage="usage: scaling_study.sh strong|weak [sbatch options...] [-- script arguments...]"
root=$(cd "$(dirname "$0")/../.." && pwd)
export DESCENT_ROOT=${DESCENT_ROOT:-$root}
mode=${1:-}
case $mode in strong | weak) shift ;; *)
  echo "$usage" >&2
  exit 2
  ;;
esac

array_options=()
table_options=()
script_arguments=()
while [ $# -gt 0 ]; do
  case $1 in
  --)
    shift
    script_arguments=("$@")
    break
    ;;
  --partition=* | --account=* | --qos=* | --reservation=* | --clusters=* | --chdir=*)
    array_options+=("$1")
    table_options+=("$1")
    ;;
  --partition | --account | --qos | --reservation | --clusters | --chdir | -p | -A | -q | -M | -D)
    [ $# -ge 2 ] || { echo "scaling_study.sh: $1 needs a value" >&2; exit 2; }
    array_options+=("$1" "$2")
    table_options+=("$1" "$2")
    shift
    ;;
  *)
    array_options+=("$1")
    ;;
  esac
  shift
done

# --parsable prints "JOBID" or "JOBID;CLUSTER".
array=$(sbatch --parsable "${array_options[@]}" "$DESCENT_ROOT/jobs/slurm/${mode}_scaling.sbatch" \
  "${script_arguments[@]}")
array=${array%%;*}
if ! table=$(sbatch --parsable --dependency="afterany:$array" "${table_options[@]}" \
  "$DESCENT_ROOT/jobs/slurm/scaling_table.sbatch" "$mode" "$array"); then
  echo "scaling_study.sh: array job $array submitted, the table job not; once it has ended:" >&2
  echo "  sbatch --dependency=afterany:$array $DESCENT_ROOT/jobs/slurm/scaling_table.sbatch $mode $array" >&2
  exit 1
fi
table=${table%%;*}
echo "scaling_study.sh: $mode scaling: array job $array, table job $table (after it)"
echo "scaling_study.sh: table and plot: runs/scaling-$mode-$array.csv, .md, .png"
