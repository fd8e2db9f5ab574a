#!/usr/bin/env bash
# Where Jacobi's spectrum in the contact scenes comes from, and what solving
# each contact cluster's block exactly would give (docs/contact.md, "What
# limits the iterations"): for each scene and frame, one rank runs the
# scene's own steps to that frame, one Newton step from there, and at its
# result the extreme eigenvalues of P^-1 H for P = Jacobi's diagonal (with
# the contact terms' row sums), P = diag(A) + the contact blocks, and two
# references: Jacobi on the elastic part alone, and the exact elastic
# operator with the contact terms' row sums (what a perfect multilevel
# preconditioner that takes contact as a diagonal could reach). The
# driver's header (bench/pair_block_spectrum.cpp) says how.
#
#   bench/pair_block_spectrum.sh [BUILD_DIR]      # default build
#
# Writes bench/results/contact/pair_block_spectrum.csv (replaced) and a log
# beside it with the machine. The fine snowman (ball cells 20/15/12, 78,618
# tets, as in multilevel_pairs_trial.md) takes a few minutes.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
out=$root/bench/results/contact
csv=$out/pair_block_spectrum.csv
log=$out/pair_block_spectrum.log
cmake --build "$build" --target pair_block_spectrum_bench -j2 >/dev/null
bench=$build/tests/mpi/pair_block_spectrum_bench
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
# The snowman with balls of 20, 15 and 12 cells across (the coarse job's 8, 6, 5).
sed -e 's/cells = 8,/cells = 20,/' -e 's/cells = 6,/cells = 15,/' -e 's/cells = 5,/cells = 12,/' \
  "$root/jobs/contact/snowman.toml" >"$scratch/snowman_fine.toml"

{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), $(git -C "$root" rev-parse --short HEAD)"
  echo "# $(lscpu | sed -n 's/^Model name: *//p'), $(getconf _NPROCESSORS_ONLN) logical cores, one rank, OMP_NUM_THREADS=1"
} >"$log"
"$bench" --header >"$csv"
cases=(
  "snowman 10" "snowman 40" "pile 20" "pile 60" "bowling 30" "bowling 45"
  "head_on 10" "cars_sideways 20" "cars_spin 30" "cars_spin 36" "cars_spin 40" "cars_spin 44"
  "snowman_fine 30"
)
for c in "${cases[@]}"; do
  read -r scene frames <<<"$c"
  file=$root/jobs/contact/$scene.toml
  [[ $scene == snowman_fine ]] && file=$scratch/snowman_fine.toml
  # Paths in the log relative to the repository, the scratch folder as SCRATCH.
  echo "$scene frame $frames: $bench $file $frames" | sed -e "s|$root/||g" -e "s|$scratch|SCRATCH|g" >>"$log"
  start=$(date +%s)
  "$bench" "$file" "$frames" 2>>"$log" | sed "s|^[^,]*,|$scene,|" >>"$csv"
  echo "  $(($(date +%s) - start)) s" >>"$log"
done
