// The position constraint of a contact pair for contact.method =
// "projection" (kernels/pair_projection.hpp): which paths make a pair
// active and the plane they give it, a full projection meeting the
// constraint exactly while keeping the pair's momentum, held vertices
// staying where they are, and Coulomb friction cutting the slip by mu times
// the normal correction and no further.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "kernels/pair_projection.hpp"

namespace descent {
namespace {

using X = std::array<double, 12>;

// A vertex above the triangle (0,0,0) (1,0,0) (0,1,0), at height z and
// tangential place (u, v).
X vertex_over_triangle(double u, double v, double z) {
  return {u, v, z, 0, 0, 0, 1, 0, 0, 0, 1, 0};
}

double momentum(const double* dx, const double* mass, int axis) {
  double p = 0;
  for (int k = 0; k < 4; ++k) p += mass[k] * dx[3 * k + axis];
  return p;
}

TEST(PairProjection, APathThatStaysBeyondReachIsInactive) {
  const double dh = 0.01;
  const X x0 = vertex_over_triangle(0.2, 0.2, 0.5);
  const X x1 = vertex_over_triangle(0.2, 0.2, 0.1);
  EXPECT_FALSE(pair_constraint(PairKind::vertex_triangle, x0.data(), x1.data(), dh).active);
}

TEST(PairProjection, AVertexThroughTheTriangleIsPulledBackToTheSideItCameFrom) {
  const double dh = 0.01;
  const X x0 = vertex_over_triangle(0.2, 0.3, 0.5);
  const X x1 = vertex_over_triangle(0.25, 0.3, -0.4);  // went through
  const PairConstraint<double> con =
      pair_constraint(PairKind::vertex_triangle, x0.data(), x1.data(), dh);
  ASSERT_TRUE(con.active);
  // The plane is the triangle's, facing the side the vertex came from.
  EXPECT_NEAR(con.n[2], 1.0, 1e-12);
  EXPECT_NEAR(pair_constraint_value(con, x1.data(), dh), -0.4 - dh, 1e-12);
  const double inv_mass[4] = {1.0 / 2, 1.0 / 3, 1.0 / 4, 1.0 / 5};
  const double mass[4] = {2, 3, 4, 5};
  double dx[12];
  const double closed = project_pair(con, x1.data(), x0.data(), inv_mass, dh, 0.0, 1.0, dx);
  EXPECT_NEAR(closed, 0.4 + dh, 1e-12);
  X y = x1;
  for (int k = 0; k < 12; ++k) y[k] += dx[k];
  EXPECT_NEAR(pair_constraint_value(con, y.data(), dh), 0.0, 1e-12);
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(momentum(dx, mass, axis), 0.0, 1e-12);
  // The light vertex takes the larger share.
  EXPECT_GT(dx[2], 0.0);
  EXPECT_LT(dx[5], 0.0);
  // Half the relaxation closes half.
  project_pair(con, x1.data(), x0.data(), inv_mass, dh, 0.0, 0.5, dx);
  y = x1;
  for (int k = 0; k < 12; ++k) y[k] += dx[k];
  EXPECT_NEAR(pair_constraint_value(con, y.data(), dh), -0.5 * (0.4 + dh), 1e-12);
}

TEST(PairProjection, HeldVerticesStayAndAMetConstraintMovesNothing) {
  const double dh = 0.01;
  const X x0 = vertex_over_triangle(0.2, 0.3, 0.5);
  const X x1 = vertex_over_triangle(0.2, 0.3, -0.1);
  const PairConstraint<double> con =
      pair_constraint(PairKind::vertex_triangle, x0.data(), x1.data(), dh);
  ASSERT_TRUE(con.active);
  const double held_triangle[4] = {1, 0, 0, 0};
  double dx[12];
  project_pair(con, x1.data(), x0.data(), held_triangle, dh, 0.0, 1.0, dx);
  for (int k = 3; k < 12; ++k) EXPECT_EQ(dx[k], 0.0);
  EXPECT_NEAR(dx[2], 0.1 + dh, 1e-12);
  const double all_held[4] = {0, 0, 0, 0};
  EXPECT_EQ(project_pair(con, x1.data(), x0.data(), all_held, dh, 0.0, 1.0, dx), 0.0);
  const X met = vertex_over_triangle(0.2, 0.3, 2 * dh);
  const double free[4] = {1, 1, 1, 1};
  EXPECT_EQ(project_pair(con, met.data(), x0.data(), free, dh, 0.0, 1.0, dx), 0.0);
  for (double d : dx) EXPECT_EQ(d, 0.0);
}

// The vertex slides 0.2 along x while it goes 0.05 through a held
// triangle: friction cuts its slip by mu times the 0.05 + dh it is pushed
// back, and at most to zero.
TEST(PairProjection, FrictionCutsTheSlipByMuTimesTheNormalCorrection) {
  const double dh = 0.01;
  const X x0 = vertex_over_triangle(0.2, 0.3, 0.005);
  const X x1 = vertex_over_triangle(0.4, 0.3, -0.05);
  const PairConstraint<double> con =
      pair_constraint(PairKind::vertex_triangle, x0.data(), x1.data(), dh);
  ASSERT_TRUE(con.active);
  const double held_triangle[4] = {1, 0, 0, 0};
  double dx[12];
  const double depth = 0.05 + dh;
  for (double mu : {0.5, 10.0}) {
    project_pair(con, x1.data(), x0.data(), held_triangle, dh, mu, 1.0, dx);
    const double slip_after = (x1[0] + dx[0]) - x0[0];
    EXPECT_NEAR(slip_after, std::max(0.0, 0.2 - mu * depth), 1e-12) << "mu " << mu;
    EXPECT_NEAR(dx[1], 0.0, 1e-15);
  }
}

TEST(PairProjection, EdgesThatPassThroughEachOtherArePushedApartKeepingMomentum) {
  const double dh = 0.01;
  // Edge p along x at z = 0.3 moving down through edge q along y at z = 0.
  const X x0 = {-1, 0.1, 0.3, 1, 0.1, 0.3, 0.2, -1, 0, 0.2, 1, 0};
  X x1 = x0;
  for (int k : {2, 5}) x1[k] = -0.2;
  const PairConstraint<double> con = pair_constraint(PairKind::edge_edge, x0.data(), x1.data(), dh);
  ASSERT_TRUE(con.active);
  EXPECT_NEAR(std::abs(con.n[2]), 1.0, 1e-9);
  const double inv_mass[4] = {1, 1, 0.5, 0.5};
  const double mass[4] = {1, 1, 2, 2};
  double dx[12];
  project_pair(con, x1.data(), x0.data(), inv_mass, dh, 0.0, 1.0, dx);
  X y = x1;
  for (int k = 0; k < 12; ++k) y[k] += dx[k];
  EXPECT_NEAR(pair_constraint_value(con, y.data(), dh), 0.0, 1e-12);
  for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(momentum(dx, mass, axis), 0.0, 1e-12);
  // Edge p ends above edge q again: the points of the plane (p's at
  // x = 0.2, q's at y = 0.1) dh apart, and the edges, tilted by the
  // correction's weights, within 1% of it (the plane is the pass's
  // linearisation; the next pass starts from the distance as it is).
  EXPECT_NEAR(0.4 * y[2] + 0.6 * y[5] - (0.45 * y[8] + 0.55 * y[11]), dh, 1e-12);
  EXPECT_NEAR(std::sqrt(pair_distance(PairKind::edge_edge, y.data(), false).d2), dh, 1e-2 * dh);
}

}  // namespace
}  // namespace descent
