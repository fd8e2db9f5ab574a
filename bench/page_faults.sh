#!/usr/bin/env bash
# What fresh memory costs on this machine, in 4 KiB pages and in
# transparent huge pages (GLIBC_TUNABLES=glibc.malloc.hugetlb=1): the
# set-up of a large mesh is mostly first touches (bench/setup_10m.py), and
# which page size wins depends on the machine (a virtual machine's host
# backs a guest's huge page at its own cost). RUNS processes per case,
# taken in turn; each prints the seconds of three 2 GiB fills.
#
#   bench/page_faults.sh            # appends to bench/results/setup_10m/page_faults.log
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
runs=${RUNS:-3}
log=$root/bench/results/setup_10m/page_faults.log
binary=$(mktemp -t page_faults.XXXXXX)
trap 'rm -f "$binary"' EXIT
g++ -O2 -std=c++17 -o "$binary" "$root/bench/page_faults.cpp"
{
  echo "## $(date -u '+%Y-%m-%d %H:%M') UTC, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(nproc) cores"
  echo "transparent huge pages: $(cat /sys/kernel/mm/transparent_hugepage/enabled), defrag: $(cat /sys/kernel/mm/transparent_hugepage/defrag)"
  echo "seconds per 2 GiB fill (first, second, third in one process):"
  for ((r = 1; r <= runs; ++r)); do
    echo "  4k:   $(env -u GLIBC_TUNABLES "$binary")"
    echo "  huge: $(GLIBC_TUNABLES=glibc.malloc.hugetlb=1 "$binary")"
  done
} | tee -a "$log"
