// The spectrum a preconditioner that solves each contact cluster's block
// would give, against Jacobi's: the driver of bench/pair_block_spectrum.sh
// (docs/contact.md, "Jacobi's D cannot scale a pressed pair").
//
//   pair_block_spectrum_bench SCENE.toml FRAMES [key=value ...]
//
// One rank. Runs FRAMES steps of the scene as `descent run` would, then one
// Newton step from there (solved to solver.newton_tolerance), and at its
// result q, with the step start q_t, takes the Hessian H in the positive
// semi-definite form Newton and the engine use:
//   A  the elastic element Hessians plus the vertex terms m (1/h^2 + c/h),
//   C  the contact terms (obstacles' 3x3 blocks, the pairs' 12x12 blocks),
//   H = A + C.
// Two preconditioners P:
//   jacobi  diag(A) + the absolute row sums of C (the engine's diagonal),
//   blocks  diag(A) + C: exact on the contact terms, Jacobi elsewhere. C
//           couples only the vertices of pairs, so P is block diagonal over
//           the clusters of vertices that pairs link (sparse Cholesky).
// For each, lambda_min and lambda_max of P^-1 H (Lanczos on
// G^-1 H G^-T, P = G G^T, for the largest; on its inverse for the
// smallest), the condition number kappa, and the iterations a Chebyshev
// iteration with exact bounds needs to cut the error by 1e-6:
// ln(2 / 1e-6) / ln(1 / rho), rho = (sqrt(kappa) - 1) / (sqrt(kappa) + 1).
// Rank 0 prints one CSV line (the header with --header as the only
// argument). Held dofs are left out of every matrix.
//
// C's columns come from products of the assembled operator with unit
// vectors, one per dof where the contact terms add to the diagonal: the
// operator's product with the pairs is evaluated, not stored.
#include <mpi.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <numeric>
#include <string>
#include <vector>

#include "app/scene_mesh.hpp"
#include "app/simulation.hpp"
#include "io/scene.hpp"
#include "solver/methods/hessian_operator.hpp"
#include "solver/methods/newton.hpp"

namespace {

using Sparse = Eigen::SparseMatrix<double>;
using Vector = Eigen::VectorXd;

// The largest eigenvalue of the symmetric operator `apply` on n unknowns:
// Lanczos with full reorthogonalisation, `steps` steps from a fixed start.
template <class Apply>
double largest_eigenvalue(int n, int steps, Apply&& apply) {
  steps = std::min(steps, n);
  Eigen::MatrixXd basis(n, steps + 1);
  Vector alpha(steps), beta(steps);
  Vector v = Vector::LinSpaced(n, 1.0, 2.0);  // not an eigenvector of any model here
  v.normalize();
  basis.col(0) = v;
  int made = 0;
  for (int k = 0; k < steps; ++k) {
    Vector w = apply(basis.col(k));
    alpha(k) = basis.col(k).dot(w);
    for (int pass = 0; pass < 2; ++pass)
      for (int j = 0; j <= k; ++j) w -= basis.col(j).dot(w) * basis.col(j);
    beta(k) = w.norm();
    ++made;
    if (beta(k) < 1e-12 * std::abs(alpha(k))) break;
    basis.col(k + 1) = w / beta(k);
  }
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(made, made);
  for (int k = 0; k < made; ++k) {
    t(k, k) = alpha(k);
    if (k + 1 < made) t(k, k + 1) = t(k + 1, k) = beta(k);
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(t).eigenvalues().maxCoeff();
}

struct Spectrum {
  double lambda_min = 0, lambda_max = 0;
  long factor_nonzeros = 0;  // of P's Cholesky factor
  double kappa() const { return lambda_max / lambda_min; }
  double chebyshev_iterations() const {
    const double s = std::sqrt(kappa()), rho = (s - 1) / (s + 1);
    return std::log(2 / 1e-6) / std::log(1 / rho);
  }
};

// lambda_min and lambda_max of P^-1 H (both SPD).
Spectrum spectrum(const Sparse& h, const Sparse& p, int steps) {
  Eigen::SimplicialLLT<Sparse> gp(p), gh(h);
  if (gp.info() != Eigen::Success || gh.info() != Eigen::Success)
    throw std::runtime_error("a Cholesky factorisation failed (not positive definite)");
  const int n = static_cast<int>(h.rows());
  // P = Q^T L L^T Q (Eigen: Q P Q^-1 = L L^T), G = Q^T L. K = G^-1 H G^-T.
  auto k_times = [&](const Vector& x) -> Vector {
    Vector a = gp.matrixU().solve(x);
    Vector b = gp.permutationPinv() * a;
    Vector c = h * b;
    Vector d = gp.permutationP() * c;
    return gp.matrixL().solve(d);
  };
  // K^-1 = G^T H^-1 G.
  auto k_inverse_times = [&](const Vector& x) -> Vector {
    Vector a = gp.matrixL() * x;
    Vector b = gp.permutationPinv() * a;
    Vector c = gh.solve(b);
    Vector d = gp.permutationP() * c;
    return gp.matrixU() * d;
  };
  Spectrum s;
  s.lambda_max = largest_eigenvalue(n, steps, k_times);
  s.lambda_min = 1 / largest_eigenvalue(n, steps, k_inverse_times);
  s.factor_nonzeros = static_cast<long>(Sparse(gp.matrixL()).nonZeros());
  return s;
}

int run(int argc, char** argv) {
  using namespace descent;
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (argc == 2 && std::string(argv[1]) == "--header") {
    std::printf(
        "scene,frames,dofs,contact_dofs,clusters,largest_cluster_dofs,newton_iterations,"
        "jacobi_lambda_min,jacobi_lambda_max,jacobi_kappa,jacobi_chebyshev_iterations,"
        "blocks_lambda_min,blocks_lambda_max,blocks_kappa,blocks_chebyshev_iterations,"
        "blocks_factor_nonzeros,elastic_jacobi_kappa,ideal_lambda_min,ideal_lambda_max,"
        "ideal_kappa\n");
    return 0;
  }
  if (argc < 3 || ranks != 1) {
    std::fprintf(stderr,
                 "usage (one rank): pair_block_spectrum_bench SCENE FRAMES [key=value ...]\n");
    return 2;
  }
  const int frames = std::max(0, std::atoi(argv[2]));
  const std::vector<std::string> overrides(argv + 3, argv + argc);
  const Scene scene = load_scene(argv[1], overrides);
  const Mesh mesh = build_scene_mesh(scene);
  Simulation<double> sim(MPI_COMM_WORLD, scene, mesh);
  for (int f = 0; f < frames; ++f) sim.step();

  SolverSpec newton_spec = scene.solver;
  newton_spec.method = "newton";
  newton_spec.newton_solver = "cg";
  Newton<double> newton(sim.problem(), newton_spec);
  BodyState<double> state = sim.state();
  const std::vector<double> qt = state.q;
  const StepStats stats = newton.step(state);
  const std::vector<double>& q = state.q;

  // Free dofs, numbered.
  LocalProblem<double>& problem = sim.problem();
  const std::vector<std::uint8_t>& fixed = problem.fixed_axes();
  const std::size_t all = q.size();
  std::vector<int> dof(all, -1);
  int n = 0;
  for (std::size_t k = 0; k < all; ++k)
    if (!((fixed[k / 3] >> (k % 3)) & 1)) dof[k] = n++;

  // A from the stored element Hessians and the vertex curvature.
  HessianOperator<double> op(problem);
  op.assemble(q.data(), true);
  const LocalMesh& local = sim.local_mesh();
  std::vector<Eigen::Triplet<double>> a_entries;
  const std::vector<double>& hessians = op.element_hessians();
  for (index_t t = 0; t < local.num_tets(); ++t) {
    const index_t* tet = &local.tets[4 * static_cast<std::size_t>(t)];
    for (int r = 0; r < 12; ++r)
      for (int c = 0; c < 12; ++c) {
        const int i = dof[3 * static_cast<std::size_t>(tet[r / 3]) + r % 3];
        const int j = dof[3 * static_cast<std::size_t>(tet[c / 3]) + c % 3];
        if (i >= 0 && j >= 0)
          a_entries.emplace_back(i, j, hessians[144 * static_cast<std::size_t>(t) + 12 * r + c]);
      }
  }
  for (std::size_t k = 0; k < all; ++k)
    if (dof[k] >= 0) a_entries.emplace_back(dof[k], dof[k], op.vertex_curvature()[k]);
  Sparse a(n, n);
  a.setFromTriplets(a_entries.begin(), a_entries.end());
  const std::vector<double> elastic_diagonal = op.diagonal();

  // C's columns on the dofs where the contact terms add to the diagonal.
  op.assemble_contact(q.data(), qt.data(), true);
  std::vector<Eigen::Triplet<double>> c_entries;
  std::vector<double> e(all, 0.0), column(all, 0.0);
  int contact_dofs = 0;
  for (std::size_t k = 0; k < all; ++k) {
    if (dof[k] < 0 || op.diagonal()[k] == elastic_diagonal[k]) continue;
    ++contact_dofs;
    e[k] = 1;
    op.apply(e.data(), column.data());
    e[k] = 0;
    Vector a_column = a.col(dof[k]);
    for (std::size_t i = 0; i < all; ++i) {
      if (dof[i] < 0) continue;
      const double value = column[i] - a_column(dof[i]);
      if (value != 0) c_entries.emplace_back(dof[i], dof[k], value);
    }
  }
  Sparse c(n, n);
  c.setFromTriplets(c_entries.begin(), c_entries.end());
  c = 0.5 * (c + Sparse(c.transpose()));  // round-off of the difference
  const Sparse h = a + c;

  Sparse jacobi(n, n), blocks(n, n), elastic_jacobi(n, n), ideal(n, n);
  std::vector<Eigen::Triplet<double>> jacobi_entries, block_entries, elastic_entries;
  Vector c_row_sums = Vector::Zero(n);
  for (int k = 0; k < c.outerSize(); ++k)
    for (Sparse::InnerIterator it(c, k); it; ++it) {
      c_row_sums(it.row()) += std::abs(it.value());
      block_entries.emplace_back(it.row(), it.col(), it.value());
    }
  for (int i = 0; i < n; ++i) {
    jacobi_entries.emplace_back(i, i, a.coeff(i, i) + c_row_sums(i));
    block_entries.emplace_back(i, i, a.coeff(i, i));
  }
  jacobi.setFromTriplets(jacobi_entries.begin(), jacobi_entries.end());
  for (int i = 0; i < n; ++i) elastic_entries.emplace_back(i, i, a.coeff(i, i));
  elastic_jacobi.setFromTriplets(elastic_entries.begin(), elastic_entries.end());
  ideal = a + Sparse(jacobi - elastic_jacobi);
  blocks.setFromTriplets(block_entries.begin(), block_entries.end());

  // Clusters: connected pieces of C's pattern (union-find over its entries).
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (int k = 0; k < c.outerSize(); ++k)
    for (Sparse::InnerIterator it(c, k); it; ++it)
      parent[root(static_cast<int>(it.row()))] = root(static_cast<int>(it.col()));
  std::vector<int> size(n, 0);
  for (int i = 0; i < n; ++i)
    if (c_row_sums(i) > 0) ++size[root(i)];
  const int clusters =
      static_cast<int>(std::count_if(size.begin(), size.end(), [](int s) { return s > 1; }));
  const int largest = *std::max_element(size.begin(), size.end());

  constexpr int kLanczosSteps = 200;
  const Spectrum sj = spectrum(h, jacobi, kLanczosSteps);
  const Spectrum sb = spectrum(h, blocks, kLanczosSteps);
  const Spectrum se = spectrum(a, elastic_jacobi, kLanczosSteps);
  const Spectrum si = spectrum(h, ideal, kLanczosSteps);
  std::printf(
      "%s,%d,%d,%d,%d,%d,%d,%.4e,%.4e,%.4e,%.0f,%.4e,%.4e,%.4e,%.0f,%ld,%.4e,%.4e,%.4e,%.4e\n",
      argv[1], frames, n, contact_dofs, clusters, largest, stats.iterations, sj.lambda_min,
      sj.lambda_max, sj.kappa(), sj.chebyshev_iterations(), sb.lambda_min, sb.lambda_max,
      sb.kappa(), sb.chebyshev_iterations(), sb.factor_nonzeros, se.kappa(), si.lambda_min,
      si.lambda_max, si.kappa());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int status = 1;
  try {
    status = run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pair_block_spectrum_bench: %s\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return status;
}
