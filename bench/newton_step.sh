#!/usr/bin/env bash
# One Newton step to |g| <= 1e-10 |g0| (the first frame of the scene, from
# rest), per Newton linear solver: cg (our Jacobi CG), cg_multilevel (our CG
# preconditioned by the multilevel V-cycle), ldlt (rank 0's sparse
# LDL^T), petsc (CG + GAMG), petsc with -pc_type hypre (CG + BoomerAMG at
# hypre's defaults) and hypre_tuned (BoomerAMG with the usual 3D settings:
# strong threshold 0.5, HMIS coarsening, ext+i interpolation, P_max 4, one
# level of aggressive coarsening), on
# the 41K, 82K and 158K helix (jobs/helix.toml) and the armadillo
# (jobs/study/armadillo.toml; skipped when ../shared/meshes lacks it), on 1
# and 2 ranks. Each line of the CSV: median step time of REPEATS steps from
# the same state (slowest rank), Newton iterations, total Krylov iterations,
# and the MPI_Allreduce calls of one step counted at the MPI boundary (ours
# and PETSc's). Writes bench/results/newton_step/newton_step.csv (appends;
# remove it to start over) and a log beside it.
#
#   bench/newton_step.sh [BUILD_DIR]          # default build-petsc
#   REPEATS=3 SLOW_REPEATS=1 RANKS="1 2" MESHES="41k 82k 158k armadillo" \
#   SOLVERS="petsc hypre hypre_tuned cg ldlt" TIME_LIMIT=900 bench/newton_step.sh
#
# cg, ldlt and hypre (defaults) take minutes on the large meshes: they run
# SLOW_REPEATS times (default 1) except on the 41K helix; a run past
# TIME_LIMIT seconds (LDLT_TIME_LIMIT for ldlt, default 300) is recorded as a
# timeout. One OpenMP thread per rank.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build-petsc}
repeats=${REPEATS:-3}
slow_repeats=${SLOW_REPEATS:-1}
ranks_list=${RANKS:-"1 2"}
meshes=${MESHES:-"41k 82k 158k armadillo"}
solvers=${SOLVERS:-"petsc hypre hypre_tuned cg ldlt"}
limit=${TIME_LIMIT:-900}
ldlt_limit=${LDLT_TIME_LIMIT:-300}
out=$root/bench/results/newton_step
mkdir -p "$out"
csv=$out/newton_step.csv
log=$out/newton_step.log

cmake --build "$build" --target newton_step_bench -j2 >/dev/null
bench=$build/tests/mpi/newton_step_bench
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[[ -s $csv ]] || { printf 'mesh,'; "$bench" --header; } >"$csv"

for mesh in $meshes; do
  if [[ $mesh == armadillo ]]; then
    scene=$root/jobs/study/armadillo.toml
    armadillo=$root/../shared/meshes/armadillo_10k.node  # as the scene's mesh.file
    if [[ ! -f $armadillo ]]; then
      echo "armadillo: $armadillo absent, skipped" | tee -a "$log"
      continue
    fi
    mesh_keys=()
  else
    scene=$root/jobs/helix.toml
    mesh_keys=("mesh.helix.preset='$mesh'" "solver.accuracy=0")
  fi
  for np in $ranks_list; do
    for solver in $solvers; do
      keys=("${mesh_keys[@]}")
      case $solver in
        hypre) keys+=("solver.newton_solver='petsc'" "solver.petsc_options='-pc_type hypre'") ;;
        hypre_tuned)
          keys+=("solver.newton_solver='petsc'"
                 "solver.petsc_options='-pc_type hypre -pc_hypre_boomeramg_strong_threshold 0.5 -pc_hypre_boomeramg_coarsen_type HMIS -pc_hypre_boomeramg_interp_type ext+i -pc_hypre_boomeramg_P_max 4 -pc_hypre_boomeramg_agg_nl 1'") ;;
        cg) keys+=("solver.newton_solver='cg'" "solver.preconditioner='jacobi'") ;;
        cg_multilevel) keys+=("solver.newton_solver='cg'" "solver.preconditioner='multilevel'") ;;
        *) keys+=("solver.newton_solver='$solver'") ;;
      esac
      n=$repeats
      [[ ($solver == cg || $solver == ldlt || $solver == hypre) && $mesh != 41k ]] &&
        n=$slow_repeats
      t=$limit
      [[ $solver == ldlt ]] && t=$ldlt_limit
      echo "$(date -u +%T) $mesh np=$np $solver x$n" | tee -a "$log"
      if line=$(timeout "$t" mpiexec -n "$np" --oversubscribe "$bench" "$scene" "$n" \
                  "${keys[@]}" 2>>"$log" | tail -1) && [[ -n $line ]]; then
        line=$(awk -F, -v s="$solver" 'BEGIN { OFS = "," } { $2 = s; print }' <<<"$line")
        echo "$mesh,$line" | tee -a "$csv" "$log"
      else
        echo "$mesh,$np,$solver,timeout (${t} s) or failure" | tee -a "$csv" "$log"
      fi
    done
  done
done
