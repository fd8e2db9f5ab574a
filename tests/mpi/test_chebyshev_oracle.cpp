// Explicit Chebyshev keys reproduce the fixed-parameter method exactly as it
// was before the automatic parameters (issue 11): per frame the iteration
// count, rollbacks and final alpha of runs recorded by the earlier stepper
// (tests/mpi/data/chebyshev_fixed_oracle.txt), the energy at the last check
// and a digest of the positions to round-off. With DESCENT_WRITE_ORACLE=FILE
// the test writes that file from the current code instead (rank 0).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "gather_positions.hpp"
#include "small_scenes.hpp"

namespace descent {
namespace {

struct FrameRecord {
  int iterations = 0, rollbacks = 0;
  double alpha = 0, energy = 0;
};

struct RunRecord {
  std::vector<FrameRecord> frames;
  double position_sum = 0, weighted_sum = 0;
};

// The fixed parameters of the paper's method, set explicitly. The oracle's
// runs were recorded on the partition METIS makes in one try and in the
// generator's vertex order (before partition.reorder): in float, and with
// conversion, 8 frames on another partition or another local order (another
// order of the sums) drift by more than the round-off the comparison allows.
// That the local order changes results only by round-off in one step is
// test_local_order's to check.
Scene fixed_scene(const std::string& name) {
  Scene scene = testing::fixed_chebyshev(testing::small_helix_scene());
  scene.partition.tries = 1;
  scene.partition.reorder = "none";
  SolverSpec& s = scene.solver;
  if (name == "conversion") {
    scene.material.model = "stvk";
    scene.material.conversion.enabled = true;
  } else if (name == "phases") {
    s.phase_rho = {0.9, 0.97};
    s.phase_lengths = {40};
  }
  return scene;
}

template <class Real>
RunRecord run(const Scene& scene, int frames) {
  const Mesh mesh = build_scene_mesh(scene.mesh);
  Simulation<Real> sim(MPI_COMM_WORLD, scene, mesh);
  RunRecord record;
  for (int f = 0; f < frames; ++f) {
    const StepStats stats = sim.step();
    record.frames.push_back({stats.iterations, stats.rollbacks, stats.alpha, stats.energy});
  }
  const std::vector<double> q = testing::gather_positions(MPI_COMM_WORLD, sim, mesh.num_vertices());
  for (std::size_t k = 0; k < q.size(); ++k) {
    record.position_sum += q[k];
    record.weighted_sum += q[k] * static_cast<double>((k * 2654435761u) % 1000) / 1000.0;
  }
  return record;
}

std::string key(const std::string& name, int ranks) { return name + "/np" + std::to_string(ranks); }

// "KEY frame iterations rollbacks alpha energy" and "KEY digest sum weighted".
std::map<std::string, RunRecord> read_oracle(const std::string& path) {
  std::map<std::string, RunRecord> oracle;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string k, what;
    s >> k >> what;
    RunRecord& r = oracle[k];
    if (what == "digest") {
      s >> r.position_sum >> r.weighted_sum;
    } else {
      FrameRecord f;
      s >> f.iterations >> f.rollbacks >> f.alpha >> f.energy;
      r.frames.push_back(f);
    }
  }
  return oracle;
}

void write_record(std::FILE* out, const std::string& k, const RunRecord& r) {
  for (std::size_t f = 0; f < r.frames.size(); ++f)
    std::fprintf(out, "%s %zu %d %d %.17g %.17g\n", k.c_str(), f + 1, r.frames[f].iterations,
                 r.frames[f].rollbacks, r.frames[f].alpha, r.frames[f].energy);
  std::fprintf(out, "%s digest %.17g %.17g\n", k.c_str(), r.position_sum, r.weighted_sum);
}

class ChebyshevOracle : public ::testing::TestWithParam<std::string> {};

TEST_P(ChebyshevOracle, ExplicitKeysReproduceTheFixedMethod) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const std::string name = GetParam();
  constexpr int kFrames = 8;
  const Scene scene = fixed_scene(name == "float" ? "plain" : name);
  const RunRecord got = name == "float" ? run<float>(scene, kFrames) : run<double>(scene, kFrames);
  if (rank != 0) return;
  const std::string k = key(name, size);

  if (const char* path = std::getenv("DESCENT_WRITE_ORACLE")) {
    std::FILE* out = std::fopen(path, "a");
    ASSERT_NE(out, nullptr) << path;
    write_record(out, k, got);
    std::fclose(out);
    GTEST_SKIP() << "wrote " << k << " to " << path;
  }
  const std::map<std::string, RunRecord> oracle =
      read_oracle(DESCENT_SOURCE_DIR "/tests/mpi/data/chebyshev_fixed_oracle.txt");
  const auto it = oracle.find(k);
  if (it == oracle.end()) GTEST_SKIP() << "no oracle for " << k << " (recorded: np 1 and 3)";
  const RunRecord& want = it->second;
  ASSERT_EQ(want.frames.size(), got.frames.size());
  // Energies are sums whose order may differ from the earlier code: equal to
  // round-off. Counts and alpha (products of gamma) are exact.
  const double energy_tolerance = name == "float" ? 1e-6 : 1e-12;
  for (std::size_t f = 0; f < got.frames.size(); ++f) {
    EXPECT_EQ(got.frames[f].iterations, want.frames[f].iterations) << k << " frame " << f + 1;
    EXPECT_EQ(got.frames[f].rollbacks, want.frames[f].rollbacks) << k << " frame " << f + 1;
    EXPECT_EQ(got.frames[f].alpha, want.frames[f].alpha) << k << " frame " << f + 1;
    EXPECT_NEAR(got.frames[f].energy, want.frames[f].energy,
                energy_tolerance * std::abs(want.frames[f].energy))
        << k << " frame " << f + 1;
  }
  EXPECT_NEAR(got.position_sum, want.position_sum, 1e-12 * std::abs(want.position_sum)) << k;
  EXPECT_NEAR(got.weighted_sum, want.weighted_sum, 1e-12 * std::abs(want.weighted_sum)) << k;
}

INSTANTIATE_TEST_SUITE_P(Cases, ChebyshevOracle,
                         ::testing::Values("plain", "float", "conversion", "phases"));

}  // namespace
}  // namespace descent
