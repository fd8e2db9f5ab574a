// What the machine allows, measured with the compiler flags of the build
// (the same CMAKE_CXX_FLAGS as descent, so the same instruction set) and the
// ranks and threads of the run being judged: every rank measures at once
// and the rates are summed over ranks.
//
//   mpiexec -n R roofline_machine_rates BYTES_PER_RANK
//
// Prints "key value" lines (bench/roofline.py reads them):
//   isa                      the vector extensions the compiler was allowed
//   triad_GBps_double/float  a[i] = b[i] + s c[i] over 3 arrays of
//                            BYTES_PER_RANK / 3 bytes per rank, counted as
//                            STREAM counts (3 words per element moved)
//   peak_GFlops_double/float independent multiply-add chains (2 flops each),
//                            no memory traffic
//   ns_<op>_double/float     one core's time per value of a square root, a
//                            division, the cube root (kernels/cube_root.hpp)
//                            and exp (kernels/exponential.hpp) taken in lanes
//                            (independent values: a throughput)
// The triad, the chains, the roots, the division and exp run in Lanes
// of the build's vector width (kernels/cpu/lanes.hpp), as descent's element pass
// does: the build has no automatic vectorisation (CMakeLists.txt says why).
#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "kernels/cpu/lanes.hpp"

namespace {

using descent::kLaneWidth;
using descent::Lanes;

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

const char* isa() {
#if defined(__AVX512F__)
  return "avx512f";
#elif defined(__AVX2__) && defined(__FMA__)
  return "avx2+fma";
#elif defined(__AVX2__)
  return "avx2";
#elif defined(__AVX__)
  return "avx";
#elif defined(__SSE2__)
  return "sse2";
#else
  return "scalar";
#endif
}

// The best of `repeats` timings of body(), every rank in step: the slowest
// rank's time of each repeat, then the fastest repeat.
template <class Body>
double timed(int repeats, Body&& body) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    MPI_Barrier(MPI_COMM_WORLD);
    const double t0 = now();
    body();
    double t = now() - t0;
    MPI_Allreduce(MPI_IN_PLACE, &t, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    if (t < best) best = t;
  }
  return best;
}

// The triad in lanes of the build's vector width, as descent's own vector
// code is written (the build compiles without automatic vectorisation).
template <class Real>
double triad_gbps(std::size_t bytes_per_rank, int ranks) {
  using L = Lanes<Real, kLaneWidth<Real>>;
  const std::size_t blocks = bytes_per_rank / (3 * sizeof(L));
  std::vector<L> a(blocks), b(blocks), c(blocks);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < blocks; ++i) a[i] = L(0), b[i] = L(1), c[i] = L(2);
  // Enough sweeps for ~50 ms per timing whatever the size.
  const std::size_t n = blocks * kLaneWidth<Real>;
  const int sweeps = static_cast<int>(std::max<std::size_t>(1, (std::size_t(1) << 27) / n / 8 + 1));
  const L s = L(Real(0.5));
  const double t = timed(7, [&] {
    for (int k = 0; k < sweeps; ++k) {
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < blocks; ++i) a[i] = b[i] + s * c[i];
    }
  });
  volatile Real sink = a[blocks / 2].v[0];
  (void)sink;
  return 3.0 * sizeof(Real) * n * sweeps * ranks / t / 1e9;
}

// kChains independent chains x <- x a + b in lanes of the build's vector
// width (kept in registers): 2 flops per lane per chain per round. Not
// inlined, and its sum kept, so that the work cannot be dropped.
template <class Real>
__attribute__((noinline)) Real multiply_add_chains(long rounds) {
  using L = Lanes<Real, kLaneWidth<Real>>;
  constexpr int kChains = 8;
  L x[kChains];
  for (int k = 0; k < kChains; ++k) x[k] = L(Real(1) + Real(k) * Real(1e-3));
  const L a = L(Real(0.999999)), b = L(Real(1e-7));
  for (long r = 0; r < rounds; ++r)
    for (int k = 0; k < kChains; ++k) x[k] = x[k] * a + b;
  Real s = 0;
  for (int k = 0; k < kChains; ++k)
    for (int l = 0; l < kLaneWidth<Real>; ++l) s += x[k].v[l];
  return s;
}

template <class Real>
double peak_gflops(int ranks) {
  const long rounds = 1L << 24;
  double sum = 0;
  const double t = timed(5, [&] {
#pragma omp parallel reduction(+ : sum)
    sum += static_cast<double>(multiply_add_chains<Real>(rounds));
  });
  volatile double sink = sum;
  (void)sink;
  return 2.0 * 8 * kLaneWidth<Real> * rounds * omp_get_max_threads() * ranks / t / 1e9;
}

// One core's ns per value of an operation on lanes (as the element math
// divides and takes roots and exponentials: a block of tets per
// instruction).
template <class Real, class Op>
double ns_per_lane_value(Op&& op) {
  using L = Lanes<Real, kLaneWidth<Real>>;
  constexpr int kBlocks = 512;
  std::vector<L> in(kBlocks), out(kBlocks);
  for (int i = 0; i < kBlocks; ++i) in[i] = L(Real(0.5) + Real(i) / Real(kBlocks));
  const int sweeps = 2000;
  const double t = timed(5, [&] {
    for (int s = 0; s < sweeps; ++s) {
      for (int i = 0; i < kBlocks; ++i) out[i] = op(in[i]);
      in[s % kBlocks] = out[(s * 7) % kBlocks] * L(Real(1e-9)) + L(Real(0.5));
    }
  });
  return t / (double(kBlocks) * kLaneWidth<Real> * sweeps) * 1e9;
}

template <class Real>
void print_rates(const char* name, std::size_t bytes, int ranks, int rank) {
  const double triad = triad_gbps<Real>(bytes, ranks);
  const double peak = peak_gflops<Real>(ranks);
  using L = Lanes<Real, kLaneWidth<Real>>;
  const double ns_sqrt = ns_per_lane_value<Real>([](L x) { return sqrt(x); });
  const double ns_cbrt = ns_per_lane_value<Real>([](L x) { return cube_root(x); });
  const double ns_exp = ns_per_lane_value<Real>([](L x) { return exponential(x); });
  const double ns_div = ns_per_lane_value<Real>([](L x) { return L(Real(1.5)) / x; });
  if (rank != 0) return;
  std::printf("triad_GBps_%s %.3f\npeak_GFlops_%s %.3f\n", name, triad, name, peak);
  std::printf("ns_sqrt_%s %.4f\nns_cbrt_%s %.4f\nns_exp_%s %.4f\nns_div_%s %.4f\n", name, ns_sqrt,
              name, ns_cbrt, name, ns_exp, name, ns_div);
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const double mib = argc > 1 ? std::atof(argv[1]) : 256.0;
  if (!(mib > 0)) {
    if (rank == 0)
      std::fprintf(stderr, "usage: %s [MiB per rank for the triad's 3 arrays]\n", argv[0]);
    MPI_Finalize();
    return 2;
  }
  const std::size_t bytes = static_cast<std::size_t>(mib * 1024 * 1024);
  if (rank == 0)
    std::printf("isa %s\nranks %d\nthreads %d\ntriad_MiB_per_rank %.1f\n", isa(), ranks,
                omp_get_max_threads(), mib);
  print_rates<double>("double", bytes, ranks, rank);
  print_rates<float>("float", bytes, ranks, rank);
  MPI_Finalize();
  return 0;
}
