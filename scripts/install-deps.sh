#!/usr/bin/env bash
# Installs what descent needs from Debian's packages (run as root, or with
# sudo available). Safe to re-run: apt-get skips what is already there.
set -euo pipefail
packages=(
  build-essential cmake pkg-config procps   # procps: pkill in the restart test
  openmpi-bin libopenmpi-dev      # MPI
  libmetis-dev                    # partitioning: METIS, the quality reference
  libptscotch-dev                 # partitioning in parallel (optional in the build)
  libeigen3-dev
  libhdf5-openmpi-dev             # parallel HDF5 for the frames
  libgtest-dev
  libtomlplusplus-dev             # scene files
  libcli11-dev                    # command line
  slurm-wlm munge                 # tests/slurm: the job scripts under a real Slurm
  python3-h5py                    # tests/slurm; tests/cli/break_h5.py: HDF5 files broken on purpose
  python3-matplotlib              # tests/slurm: the scaling table job's plot (tools/scaling_table.py)
  python3-meshio                  # tests/cli: frames.xdmf read as a time series
  ffmpeg                          # tools/plot_run.py --movie encodes MP4s; tests/cli renders one
  gmsh                            # tests/mpi/test_hertz meshes its graded hemisphere (skips without)
  petsc-dev                       # optional: Newton with AMG, TAO's methods (docs/petsc.md)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages present"
  exit 0
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
