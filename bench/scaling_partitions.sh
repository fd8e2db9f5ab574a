#!/usr/bin/env bash
# The partitions bench/scaling_model.py reads: the 10M-tet double helix
# (jobs/helix.toml at mesh.helix.resolution = 15.4: 10,358,076 tets,
# 1,856,012 vertices) cut into P parts by a real partitioner, per part the
# partitioner's own counts (descent partition --stats) and the boundary tets
# counted from the partition file (bench/partition_boundary_tets.py).
#
#   bench/scaling_partitions.sh METHOD P...
#   bench/scaling_partitions.sh ptscotch 2 4 8 16 32 64 128 256 512 1024
#   bench/scaling_partitions.sh metis 16 128 1024
#
# Writes bench/results/scaling_model/partitions/METHOD-P.csv (part, tets,
# shared_vertices, neighbours, shared_pairs) and boundary-METHOD-P.csv, and
# appends each run's log to partitions/log.txt. The partition runs on 2 ranks
# whatever P is: PT-Scotch's parts may depend on how many ranks make them
# (METIS runs on rank 0 alone), so the count is fixed here. DESCENT_BIN
# picks the binary (default build/src/app/descent); SCRATCH (default /tmp)
# holds the ~0.8 GB partition file while it is counted, removed after.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
method=${1:?usage: scaling_partitions.sh ptscotch|metis P...}
shift
bin=$(realpath -m "${DESCENT_BIN:-$root/build/src/app/descent}")
scratch=$(realpath -m "${SCRATCH:-/tmp}")
# Paths below the repository are relative to it, as the log records them.
cd "$root"
out=bench/results/scaling_model/partitions
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1

scene=$scratch/helix_10m.toml
sed 's/^preset = "82k".*/resolution = 15.4/' "$root/jobs/helix.toml" >"$scene"
for parts in "$@"; do
  pieces=$scratch/helix_10m-$method-$parts.h5
  {
    echo "== $(date -u '+%F %T UTC') $method P=$parts; load: $(uptime | sed 's/.*load average/load average/')"
    command=(mpiexec -n 2 --oversubscribe --bind-to none "$bin" partition "$scene" -n "$parts"
      --stats "$out/$method-$parts.csv" -o "$pieces" --set "partition.method=\"$method\"")
    echo "${command[*]}"
    /usr/bin/time -f "wall %e s, peak RSS %M KB (largest process)" "${command[@]}"
    /usr/bin/python3 "$root/bench/partition_boundary_tets.py" "$pieces" "$out/boundary-$method-$parts.csv"
  } 2>&1 | tee -a "$out/log.txt"
  rm -f "$pieces" "${pieces%.h5}.xdmf"
done
