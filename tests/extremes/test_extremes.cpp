// The fast subset of the extremes suite (`ctest -L extremes`): a few cases
// of tests/extremes/extreme_cases.cpp for every model, in float and double,
// on the test's rank count, asserting what must hold at the extremes:
// - the state is never NaN or Inf, whatever happens (a step that reaches no
//   finite state keeps the last good one and names its culprit);
// - the energy at the end of a step never exceeds the energy of its initial
//   guess beyond the solver's round-off tolerance (evaluated here, apart
//   from the solver; not with model conversion, whose energy moves);
// - cases the solver does hold run to the end finite, and a collapsed body
//   recovers its rest shape with conversion on.
// What does not hold (jobs/extremes/ sweep, docs/extremes.md) is not
// asserted away: the needle case may stop, but then it must name the needle.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <string>
#include <tuple>

#include "run_case.hpp"

namespace descent::extremes {
namespace {

int comm_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

// The cases of the subset and what each must do beyond never going NaN.
enum class Expect {
  completes,         // every step reaches a finite state
  recovers,          // completes, and max |sigma - 1| <= 1e-2 at the end
  names_needle_tet,  // completes, or stops naming the glued needle tet
};

struct Subset {
  const char* name;
  Expect expect;
};

// The largest time step, the stiffest material, near-incompressibility, a
// 100 m/s impact, a collapsed body, both bad tets, a 20 m/s throw at a
// floor and two bodies thrown at each other at 20 m/s, with the barrier and
// with the projection.
constexpr Subset kSubset[] = {
    {"dt_1", Expect::completes},          {"E_1e11", Expect::completes},
    {"nu_0.499", Expect::completes},      {"throw_100", Expect::completes},
    {"collapse", Expect::recovers},       {"sliver", Expect::completes},
    {"needle", Expect::names_needle_tet}, {"floor_20", Expect::completes},
    {"bodies_20", Expect::completes},     {"bodies_20_projection", Expect::completes}};

// Known exceptions, measured by the sweep and explained in docs/extremes.md:
// Fung's exponential overflows when tets are crushed (J -> 0 drives
// J^(-2/3) I1 and so exp(c3 (I1bar - 3)) to inf; conversion does not help,
// since it still evaluates the model while l < 1): the collapsed start and
// the 100 m/s impact stop at a step with no finite state. The impact's stop
// comes from a crushed predicted guess: since a failed step is retaken from
// its start (Simulation::step), it gets through on 1 rank in double and still
// stops on 3 ranks and in float, so there either outcome is accepted.
bool known_to_stop(const std::string& name, const std::string& model) {
  return name == "collapse" && model == "fung";
}
bool may_stop(const std::string& name, const std::string& model) {
  return name == "throw_100" && model == "fung";
}

template <class Real>
void check(const Case& c, const Subset& subset) {
  const Result r = run_case<Real>(MPI_COMM_WORLD, c);
  const std::string label =
      c.name + " / " + c.scene.material.model + (sizeof(Real) == 4 ? " / float" : " / double");
  EXPECT_TRUE(r.state_finite) << label << ": the state went non-finite";
  if (comm_rank() == 0) {
    for (double x : r.positions) ASSERT_TRUE(std::isfinite(x)) << label;
  }
  if (r.energy_checked) {
    EXPECT_EQ(r.energy_rises, 0) << label << ": worst rise " << r.worst_rise_ratio
                                 << " x the round-off tolerance";
  }
  if (!r.finite) {
    EXPECT_FALSE(r.failure.empty()) << label << ": a stop must name its culprit";
  }
  if (known_to_stop(c.name, c.scene.material.model)) {
    // Said in docs/extremes.md; if it starts to hold, this fails to be updated.
    EXPECT_FALSE(r.finite) << label << " now completes: update the known exceptions";
    return;
  }
  if (may_stop(c.name, c.scene.material.model) && !r.finite) return;
  switch (subset.expect) {
    case Expect::completes:
      EXPECT_TRUE(r.finite) << label << ": stopped at frame " << r.failed_frame << ", "
                            << r.failure;
      break;
    case Expect::recovers:
      EXPECT_TRUE(r.finite) << label << ": stopped at frame " << r.failed_frame << ", "
                            << r.failure;
      if (comm_rank() == 0 && r.finite) {
        EXPECT_LE(r.worst_stretch, 1e-2) << label << ": max |sigma - 1| after recovery";
      }
      break;
    case Expect::names_needle_tet:
      if (!r.finite) {
        // The glued needle is the mesh's last tet.
        const std::string needle = "tet " + std::to_string(c.mesh.num_tets() - 1);
        EXPECT_NE(r.failure.find(needle), std::string::npos)
            << label << ": the stop names " << r.failure << ", not the needle (" << needle << ")";
      }
      break;
  }
}

class Extremes : public ::testing::TestWithParam<std::tuple<Subset, std::string>> {};

TEST_P(Extremes, NeverNaNEnergyNeverRisesAndHoldsWhereItShould) {
  const auto& [subset, model] = GetParam();
  Case c = make_case(subset.name, model);
  // The helix cases run 3 of the sweep's 10 steps here: corotated and arap
  // (an SVD per tet per iteration) would take most of the budget otherwise.
  if (c.scene.mesh.generator == "double_helix") c.frames = 3;
  check<double>(c, subset);
  check<float>(c, subset);
}

std::string test_name(const ::testing::TestParamInfo<Extremes::ParamType>& info) {
  std::string name = std::string(std::get<0>(info.param).name) + "_" + std::get<1>(info.param);
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Subset, Extremes,
                         ::testing::Combine(::testing::ValuesIn(kSubset),
                                            ::testing::ValuesIn(model_names())),
                         test_name);

}  // namespace
}  // namespace descent::extremes
