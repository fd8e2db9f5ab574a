#!/usr/bin/env bash
# Issue 11's figures: Chebyshev with the automatic parameters against its
# fixed defaults, NCG and L-BFGS. Results in $RESULTS/../chebyshev_auto/
# (bench/results/chebyshev_auto by default), each with its machine.txt.
#   jobs/study/automatic.sh [pareto] [spectrum] [mainjob] [robustness]
#  pareto:     time to e <= 1e-1 .. 1e-5 per method (wall and rank 0's
#              processor time, medians of 3), 41K and 82K helix, the
#              armadillo and a stiff armadillo (E = 10 MPa), 1 and 2 ranks
#  spectrum:   lambda_min, lambda_max per step over a run, estimated every
#              step (drift), and the estimates' cost at the default interval
#  mainjob:    e at the end of every step of the main job (82K helix, 2
#              ranks, 60 frames) with solver.accuracy = 1e-2 and with the
#              paper's fixed 96 iterations, against Newton per step
#  robustness: rollbacks and non-finite trials per scene, this build against
#              OLD (a build from before issue 11, when set)
#  accuracy:   solver.accuracy = 1e-1 .. 1e-4 per step against Newton: the
#              41K helix over 12 steps, the armadillos over 6
#  tune:       descent tune (1 phase) on the 41K helix and the stiff
#              armadillo, against the automatic parameters at the same states
# SCENES="helix41k armadillo" limits the pareto part to those scenes.
# The armadillo parts are skipped with a message without ../shared/meshes.
source "$(dirname "$0")/common.sh"
parts=("$@")
[ ${#parts[@]} -gt 0 ] || parts=(pareto spectrum mainjob robustness)
base=${AUTO_RESULTS:-bench/results/chebyshev_auto}
mkdir -p "$base"
armadillo=../shared/meshes/armadillo_10k.node
have_armadillo=1
[ -f "$armadillo" ] || { echo "automatic.sh: $armadillo not found: armadillo parts skipped" >&2; have_armadillo=0; }

# name | scene arguments | iterations: automatic, fixed, ncg, lbfgs
scenes=(
  "helix41k|jobs/helix.toml --set mesh.helix.preset='\"41k\"' --set solver.accuracy=0 --set solver.iterations=96 --set solver.preconditioner='\"jacobi\"'|500 400 300 400"
  "helix82k|jobs/helix.toml --set mesh.helix.preset='\"82k\"' --set solver.accuracy=0 --set solver.iterations=96 --set solver.preconditioner='\"jacobi\"'|700 400 400 500"
  "armadillo|jobs/study/armadillo.toml --set solver.preconditioner='\"jacobi\"'|1000 400 800 1000"
  "armadillo_stiff|jobs/study/armadillo.toml --set material.young=1e7 --set solver.preconditioner='\"jacobi\"'|2500 400 2000 2500"
)

scene_args() {  # scene_args ENTRY: the scene arguments, one per line
  local entry=$1 args
  args=$(echo "$entry" | cut -d'|' -f2)
  eval "printf '%s\n' $args"
}

pareto() {
  for entry in "${scenes[@]}"; do
    name=${entry%%|*}
    # SCENES="a b": only those (default: all).
    if [ -n "${SCENES:-}" ] && [[ " $SCENES " != *" $name "* ]]; then continue; fi
    if [[ $name == armadillo* && $have_armadillo == 0 ]]; then continue; fi
    mapfile -t args < <(scene_args "$entry")
    read -r n_auto n_fixed n_ncg n_lbfgs <<<"$(echo "$entry" | cut -d'|' -f3)"
    for np in 1 2; do
      out="$base/pareto/$name/np$np"
      mkdir -p "$out"
      cmd=($MPIEXEC -n "$np" "$DESCENT" study "${args[@]}" "${TRUTH[@]}" --warmup 10 --repeats 3
           --case "automatic:method=chebyshev iterations=$n_auto"
           --case "fixed:$FIXED iterations=$n_fixed"
           --case "ncg:method=ncg iterations=$n_ncg"
           --case "lbfgs:method=lbfgs iterations=$n_lbfgs"
           --study-out "$out")
      machine "${cmd[*]}" > "$out/machine.txt"
      "${cmd[@]}" > "$out/progress.log"
    done
  done
  $PYTHON tools/plot_pareto.py "$base/pareto" --out "$base"
  gzip -f "$base"/pareto/*/np*/study.csv  # plot_pareto.py reads either
}

spectrum() {
  for entry in "${scenes[@]}"; do
    name=${entry%%|*}
    if [[ $name == armadillo* && $have_armadillo == 0 ]]; then continue; fi
    mapfile -t args < <(scene_args "$entry")
    # The run as its scene has it (the helix: to 1e-2 a step; the
    # armadillos: 96 iterations), estimating every step, then at the default.
    if [[ $name == helix* ]]; then args+=(--set solver.accuracy=1e-2 --set solver.iterations=1000); fi
    frames=60
    [[ $name == armadillo* ]] && frames=30
    for interval in 1 20; do
      out="$base/spectrum/$name/interval$interval"
      mkdir -p "$out"
      cmd=($MPIEXEC -n 1 "$DESCENT" run "${args[@]}" --set "time.frames=$frames"
           --set "solver.spectrum_interval=$interval" --set "output.every=1000"
           --set output.checkpoint_every=0 --overwrite --out "$out/run")
      machine "${cmd[*]}" > "$out/machine.txt"
      "${cmd[@]}" > "$out/progress.log" 2>&1
      cp "$out/run/stats.csv" "$out/stats.csv"
      rm -rf "$out/run"
    done
  done
  $PYTHON tools/plot_spectrum.py "$base/spectrum" --out "$base"
}

mainjob() {
  out="$base/mainjob"
  mkdir -p "$out"
  cmd=($MPIEXEC -n 2 "$DESCENT" study jobs/helix.toml "${JACOBI[@]}" "${TRUTH[@]}" --warmup 0 --frames 60 --every 1
       --repeats 1 --case "accuracy_1e-2:method=chebyshev accuracy=1e-2 iterations=1000"
       --case "fixed_96:method=chebyshev accuracy=0 iterations=96" --study-out "$out")
  machine "${cmd[*]}" > "$out/machine.txt"
  "${cmd[@]}" > "$out/progress.log"
  gzip -f "$out/study.csv"
  $PYTHON tools/plot_study.py "$out" --frames --relative --title "Main job: e at the end of each step"
}

robustness() {
  out="$base/robustness"
  mkdir -p "$out"
  builds=("new|$DESCENT")
  [ -n "${OLD:-}" ] && builds+=("old|$OLD")
  {
    echo "# build | scene | frames | rollbacks | non-finite rollbacks | steps retried | ms/frame"
    for b in "${builds[@]}"; do
      label=${b%%|*}
      binary=${b#*|}
      for entry in "helix82k|jobs/helix.toml|60" "helix82k_96|jobs/helix.toml --set solver.accuracy=0 --set solver.iterations=96|60" \
                   "helix41k_96|jobs/helix.toml --set mesh.helix.preset='\"41k\"' --set solver.accuracy=0 --set solver.iterations=96|60" \
                   "bunny|jobs/bunny.toml|40" "armadillo_stiff|jobs/study/armadillo.toml --set material.young=1e7|30" \
                   "armadillo|jobs/study/armadillo.toml|20" "box_deform|jobs/box/deform.toml|30"; do
        name=$(echo "$entry" | cut -d'|' -f1)
        frames=$(echo "$entry" | cut -d'|' -f3)
        if [[ $name == armadillo* && $have_armadillo == 0 ]]; then continue; fi
        if [[ $name == bunny && ! -f ../shared/meshes/bunny_ipc.msh ]]; then continue; fi
        # The old build knows neither accuracy nor the automatic parameters
        # (nor jobs/helix.toml's keys for them): it runs its built-in helix
        # scene, the fixed parameters at 96 iterations.
        [[ $label == old && $name == helix82k ]] && continue
        args=$(echo "$entry" | cut -d'|' -f2)
        if [[ $label == old && $name == helix* ]]; then
          args=${args//jobs\/helix.toml/}
          args=${args//--set solver.accuracy=0 /}
          args=${args//--set solver.iterations=96/}
        fi
        eval "run_args=($args)"
        rm -rf "$out/run"
        $MPIEXEC -n 2 "$binary" run "${run_args[@]}" --set "time.frames=$frames" --overwrite --quiet \
          --out "$out/run" > /dev/null 2>&1 || true
        [ -f "$out/run/stats.csv" ] || { echo "$label | $name | failed to run"; continue; }
        $PYTHON - "$label" "$name" "$out/run/stats.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[3])))
print(f"{sys.argv[1]} | {sys.argv[2]} | {len(rows)} | {sum(int(r['rollbacks']) for r in rows)} | "
      f"{sum(int(r['nonfinite_rollbacks']) for r in rows)} | "
      f"{sum(r['status'] == 'retried_from_start' for r in rows)} | "
      f"{sum(float(r['wall_ms']) for r in rows) / max(1, len(rows)):.0f}")
PY
      done
    done
  } > "$out/robustness.md"
  rm -rf "$out/run"
  # The old build by the commit of the tree it lies in, not by its path.
  local old_build="none"
  [ -n "${OLD:-}" ] && old_build="a build of commit $(git -C "$(dirname "$OLD")" rev-parse --short HEAD 2>/dev/null || echo unknown)"
  machine "jobs/study/automatic.sh robustness (OLD: $old_build); 2 ranks each" > "$out/machine.txt"
  cat "$out/robustness.md"
}

accuracy() {
  for entry in "helix41k|12|1e-1 1e-2 1e-3 1e-4" "armadillo|6|1e-2 1e-3" "armadillo_stiff|6|1e-2 1e-3"; do
    name=${entry%%|*}
    if [[ $name == armadillo* && $have_armadillo == 0 ]]; then continue; fi
    frames=$(echo "$entry" | cut -d'|' -f2)
    mapfile -t args < <(scene_args "$(printf '%s\n' "${scenes[@]}" | grep "^$name|")")
    cases=()
    for tol in $(echo "$entry" | cut -d'|' -f3); do
      cases+=(--case "tol_$tol:method=chebyshev accuracy=$tol iterations=5000")
    done
    out="$base/accuracy/$name"
    mkdir -p "$out"
    cmd=($MPIEXEC -n 1 "$DESCENT" study "${args[@]}" "${TRUTH[@]}" --warmup 5 --frames "$frames"
         --every 1 --repeats 1 "${cases[@]}" --study-out "$out")
    machine "${cmd[*]}" > "$out/machine.txt"
    "${cmd[@]}" > "$out/progress.log"
    gzip -f "$out/study.csv"
  done
  $PYTHON tools/accuracy_summary.py "$base/accuracy" > "$base/accuracy.md"
  cat "$base/accuracy.md"
}

tune() {
  for entry in "helix41k|1" "armadillo_stiff|1"; do
    name=${entry%%|*}
    if [[ $name == armadillo* && $have_armadillo == 0 ]]; then continue; fi
    mapfile -t args < <(scene_args "$(printf '%s\n' "${scenes[@]}" | grep "^$name|")")
    out="$base/tune"
    mkdir -p "$out"
    cmd=($MPIEXEC -n 1 "$DESCENT" tune "${args[@]}" --phases 1 --warmup 10 --frames 2
         --max-cycles 40 --tune-out "$out/$name.toml")
    machine "${cmd[*]}" > "$out/$name.machine.txt"
    "${cmd[@]}" 2> "$out/$name.log"
  done
}

for part in "${parts[@]}"; do
  case $part in
    pareto | spectrum | mainjob | robustness | accuracy | tune) "$part" ;;
    *) echo "automatic.sh: unknown part '$part' (pareto, spectrum, mainjob, robustness," \
            "accuracy, tune)" >&2; exit 2 ;;
  esac
done
