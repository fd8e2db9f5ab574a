// How far a contact pair may travel along a straight move
// (kernels/pair_path.hpp): moves both sides share are free, an approach
// stops where the distance reaches the floor (exactly, for a vertex heading
// straight at a face), an opening from a pressed gap is free, and along
// random moves of random pairs the distance sampled up to the returned
// fraction never falls below the floor.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "kernels/pair_path.hpp"

namespace descent {
namespace {

using X = std::array<double, 12>;

// A vertex `gap` above the face of the triangle (0,0,0), (1,0,0), (0,1,0).
X vertex_over_face(double gap) { return {0.25, 0.25, gap, 0, 0, 0, 1, 0, 0, 0, 1, 0}; }

X plus(X x, const std::array<double, 3>& move, int from, int to) {
  for (int k = from; k < to; ++k)
    for (int i = 0; i < 3; ++i) x[3 * k + i] += move[i];
  return x;
}

double distance_at(PairKind kind, const X& x0, const X& x1, double s) {
  X x;
  for (int k = 0; k < 12; ++k) x[k] = x0[k] + s * (x1[k] - x0[k]);
  return std::sqrt(pair_distance(kind, x.data(), false).d2);
}

TEST(PairPath, AMoveBothSidesShareIsFreeHoweverCloseThePair) {
  const X x0 = vertex_over_face(1e-12);
  const X x1 = plus(x0, {3.0, -2.0, 5.0}, 0, 4);
  EXPECT_EQ(pair_path_fraction(PairKind::vertex_triangle, x0.data(), x1.data(), 1e-12, 0.5e-12),
            1.0);
}

TEST(PairPath, AStraightApproachStopsWhereTheDistanceMeetsTheFloor) {
  const double d0 = 0.1, floor = 0.02;
  const X x0 = vertex_over_face(d0);
  const X x1 = plus(x0, {0, 0, -0.5}, 0, 1);  // through the face
  const double s = pair_path_fraction(PairKind::vertex_triangle, x0.data(), x1.data(), d0, floor);
  EXPECT_NEAR(s, (d0 - floor) / 0.5, 1e-12);
  EXPECT_NEAR(distance_at(PairKind::vertex_triangle, x0, x1, s), floor, 1e-12);
}

TEST(PairPath, AnObliqueApproachConvergesToTheFloorFromBelow) {
  const double d0 = 0.1, floor = 0.02;
  const X x0 = vertex_over_face(d0);
  const X x1 = plus(x0, {0.1, 0.05, -0.3}, 0, 1);  // still over the face where it meets the floor
  const double s = pair_path_fraction(PairKind::vertex_triangle, x0.data(), x1.data(), d0, floor);
  const double exact = (d0 - floor) / 0.3;
  EXPECT_LE(s, exact * (1 + 1e-15));  // round-off of the last step
  EXPECT_GT(s, exact * (1 - 1e-6));
}

TEST(PairPath, AnOpeningFromAPressedGapIsFree) {
  const double d0 = 1e-12;
  const X x0 = vertex_over_face(d0);
  const X x1 = plus(x0, {1e-3, 0, 2e-3}, 0, 1);  // away, and sideways
  EXPECT_EQ(pair_path_fraction(PairKind::vertex_triangle, x0.data(), x1.data(), d0, 0.5 * d0), 1.0);
}

TEST(PairPath, NothingFromTheFloorOrAlongANonFiniteMove) {
  const X x0 = vertex_over_face(0.1);
  X x1 = plus(x0, {0, 0, -0.05}, 0, 1);
  EXPECT_EQ(pair_path_fraction(PairKind::vertex_triangle, x0.data(), x1.data(), 0.1, 0.1), 0.0);
  x1[5] = NAN;
  EXPECT_EQ(pair_path_fraction(PairKind::vertex_triangle, x0.data(), x1.data(), 0.1, 0.01), 0.0);
}

TEST(PairPath, RandomMovesNeverGoBelowTheFloorUpToTheFraction) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int cut = 0;
  for (PairKind kind : {PairKind::vertex_triangle, PairKind::edge_edge})
    for (int trial = 0; trial < 400; ++trial) {
      X x0, x1;
      for (int k = 0; k < 12; ++k) x0[k] = u(rng);
      const double d0 = std::sqrt(pair_distance(kind, x0.data(), false).d2);
      for (int k = 0; k < 12; ++k) x1[k] = x0[k] + 0.5 * u(rng);
      const double floor = pair_kept_gap<double>(d0, 0.5);
      const double s = pair_path_fraction(kind, x0.data(), x1.data(), d0, floor);
      ASSERT_GE(s, 0.0);
      ASSERT_LE(s, 1.0);
      cut += s < 1;
      for (int j = 0; j <= 200; ++j)
        ASSERT_GE(distance_at(kind, x0, x1, s * j / 200.0), floor * (1 - 1e-9))
            << "kind " << static_cast<int>(kind) << " trial " << trial;
    }
  EXPECT_GT(cut, 20);  // the moves did reach the floor often
}

TEST(PairPath, TheKeptGapIsAShareAboveTheLeastGapAndHalfBelow) {
  const double dh = 1e-2, least = kLeastGap<double> * dh;
  EXPECT_DOUBLE_EQ(pair_kept_gap<double>(1e-3, dh), kGapKept<double> * 1e-3);
  EXPECT_DOUBLE_EQ(pair_kept_gap<double>(3 * least, dh), least);
  EXPECT_DOUBLE_EQ(pair_kept_gap<double>(least, dh), 0.5 * least);
  for (double g : {1e-12, 1e-9, 1e-6, 1e-3}) EXPECT_LT(pair_kept_gap<double>(g, dh), g);
}

}  // namespace
}  // namespace descent
