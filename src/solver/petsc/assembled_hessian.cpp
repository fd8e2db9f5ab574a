// Compiled in every build, empty without PETSc (its users refuse to start there).
#ifdef DESCENT_HAVE_PETSC

#include "solver/petsc/assembled_hessian.hpp"

#include <algorithm>
#include <utility>

#include "common/error.hpp"

namespace descent {

void check_petsc(PetscErrorCode code, const std::string& what, const char* call, const char* file,
                 int line) {
  if (code != 0)
    throw Error(detail::concat(file, ":", line, ": ", what, ": ", call, " failed with PETSc error ",
                               int(code)));
}

#define DESCENT_PETSC_CHECK(call) DESCENT_PETSC_CALL(what_, call)

template <class Real>
AssembledHessian<Real>::AssembledHessian(const LocalProblem<Real>& problem,
                                         const HessianOperator<Real>& hessian, std::string what)
    : problem_(problem), hessian_(hessian), what_(std::move(what)) {
  const LocalMesh& mesh = problem.mesh();
  const index_t nt = mesh.num_tets(), no = mesh.num_owned, nv = mesh.num_vertices();

  // The mesh's communicator: PETSc's world when the mesh spans it, or this
  // rank alone (a one-rank run beside others, e.g. a one-rank reference).
  comm_ = mesh.num_ranks == 1 ? PETSC_COMM_SELF : PETSC_COMM_WORLD;
  int size = 1, rank = 0;
  MPI_Comm_size(comm_, &size);
  MPI_Comm_rank(comm_, &rank);
  if (size != mesh.num_ranks || rank != mesh.rank)
    throw Error(detail::concat(what_, ": the mesh spans ", mesh.num_ranks, " ranks, PETSc's world ",
                               size, ": run on MPI_COMM_WORLD"));
  halo_ = std::make_unique<Halo<double>>(comm_, mesh);

  // Rows: this rank's block of 3 no, offsets by PETSc's layout (a scan).
  PetscLayout layout = nullptr;
  PetscInt first = 0, last = 0;
  DESCENT_PETSC_CHECK(PetscLayoutCreate(comm_, &layout));
  DESCENT_PETSC_CHECK(PetscLayoutSetLocalSize(layout, 3 * PetscInt(no)));
  DESCENT_PETSC_CHECK(PetscLayoutSetBlockSize(layout, 3));
  DESCENT_PETSC_CHECK(PetscLayoutSetUp(layout));
  DESCENT_PETSC_CHECK(PetscLayoutGetRange(layout, &first, &last));
  DESCENT_PETSC_CHECK(PetscLayoutDestroy(&layout));

  // Block (vertex) numbers of all local vertices: the owner's, exactly.
  exchange_.assign(3 * std::size_t(nv), 0.0);
  for (index_t v = 0; v < no; ++v) exchange_[v] = double(first / 3 + v);
  halo_->sum(exchange_.data(), 1);
  block_.resize(nv);
  for (index_t v = 0; v < nv; ++v) block_[v] = PetscInt(exchange_[v]);

  // The pattern: each tet's 4x4 vertex blocks and every owned diagonal block.
  Mat pattern = nullptr;
  DESCENT_PETSC_CHECK(MatCreate(comm_, &pattern));
  DESCENT_PETSC_CHECK(MatSetType(pattern, MATPREALLOCATOR));
  DESCENT_PETSC_CHECK(MatSetSizes(pattern, 3 * no, 3 * no, PETSC_DETERMINE, PETSC_DETERMINE));
  DESCENT_PETSC_CHECK(MatSetBlockSize(pattern, 3));
  DESCENT_PETSC_CHECK(MatSetUp(pattern));
  const std::vector<PetscScalar> zeros(144, 0.0);
  for (index_t t = 0; t < nt; ++t) {
    PetscInt blocks[4];
    for (int a = 0; a < 4; ++a) blocks[a] = block_[mesh.tets[4 * t + a]];
    DESCENT_PETSC_CHECK(
        MatSetValuesBlocked(pattern, 4, blocks, 4, blocks, zeros.data(), ADD_VALUES));
  }
  for (index_t v = 0; v < no; ++v) {
    const PetscInt b = block_[v];
    DESCENT_PETSC_CHECK(MatSetValuesBlocked(pattern, 1, &b, 1, &b, zeros.data(), ADD_VALUES));
  }
  DESCENT_PETSC_CHECK(MatAssemblyBegin(pattern, MAT_FINAL_ASSEMBLY));
  DESCENT_PETSC_CHECK(MatAssemblyEnd(pattern, MAT_FINAL_ASSEMBLY));

  DESCENT_PETSC_CHECK(MatCreate(comm_, &matrix_));
  DESCENT_PETSC_CHECK(MatSetSizes(matrix_, 3 * no, 3 * no, PETSC_DETERMINE, PETSC_DETERMINE));
  DESCENT_PETSC_CHECK(MatSetBlockSize(matrix_, 3));
  DESCENT_PETSC_CHECK(MatSetType(matrix_, MATAIJ));
  DESCENT_PETSC_CHECK(MatPreallocatorPreallocate(pattern, PETSC_TRUE, matrix_));
  DESCENT_PETSC_CHECK(MatDestroy(&pattern));
  // The pattern is final; later assemblies send the same off-rank entries.
  DESCENT_PETSC_CHECK(MatSetOption(matrix_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  DESCENT_PETSC_CHECK(MatSetOption(matrix_, MAT_SUBSET_OFF_PROC_ENTRIES, PETSC_TRUE));
  DESCENT_PETSC_CHECK(MatSetOption(matrix_, MAT_SYMMETRIC, PETSC_TRUE));
  DESCENT_PETSC_CHECK(MatSetOption(matrix_, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  DESCENT_PETSC_CHECK(MatCreateVecs(matrix_, &coordinates_, nullptr));

  // The vertex curvature is fixed for the run (HessianOperator computes it once).
  const auto& fixed = problem.fixed_axes();
  diagonal_.resize(3 * std::size_t(no));
  for (std::size_t k = 0; k < diagonal_.size(); ++k)
    diagonal_[k] = (fixed[k / 3] >> (k % 3)) & 1u ? 1.0 : double(hessian.vertex_curvature()[k]);
}

template <class Real>
AssembledHessian<Real>::~AssembledHessian() {
  if (!PetscInitializeCalled || PetscFinalizeCalled) return;  // PETSc already gone
  VecDestroy(&coordinates_);
  MatDestroy(&matrix_);
}

template <class Real>
void AssembledHessian<Real>::assemble() {
  const LocalMesh& mesh = problem_.mesh();
  const index_t nt = mesh.num_tets(), no = mesh.num_owned;
  const auto& fixed = problem_.fixed_axes();
  const Real* h = hessian_.element_hessians().data();
  DESCENT_PETSC_CHECK(MatZeroEntries(matrix_));
  // MatSetValues is not thread safe: one pass on one thread, each tet's
  // block in double with its held rows and columns zeroed on the way.
  PetscScalar block[144];
  for (index_t t = 0; t < nt; ++t) {
    bool held[12];
    for (int c = 0; c < 12; ++c) held[c] = (fixed[mesh.tets[4 * t + c / 3]] >> (c % 3)) & 1u;
    const Real* in = h + 144 * std::size_t(t);
    for (int r = 0; r < 12; ++r)
      for (int c = 0; c < 12; ++c)
        block[12 * r + c] = held[r] || held[c] ? 0.0 : double(in[12 * r + c]);
    PetscInt blocks[4];
    for (int a = 0; a < 4; ++a) blocks[a] = block_[mesh.tets[4 * t + a]];
    DESCENT_PETSC_CHECK(MatSetValuesBlocked(matrix_, 4, blocks, 4, blocks, block, ADD_VALUES));
  }
  for (index_t v = 0; v < no; ++v)
    for (int i = 0; i < 3; ++i) {
      const PetscInt row = 3 * block_[v] + i;
      DESCENT_PETSC_CHECK(
          MatSetValues(matrix_, 1, &row, 1, &row, &diagonal_[3 * v + i], ADD_VALUES));
    }
  DESCENT_PETSC_CHECK(MatAssemblyBegin(matrix_, MAT_FINAL_ASSEMBLY));
  DESCENT_PETSC_CHECK(MatAssemblyEnd(matrix_, MAT_FINAL_ASSEMBLY));
}

template <class Real>
void AssembledHessian<Real>::set_rigid_body_modes(const Real* q) {
  const LocalMesh& mesh = problem_.mesh();
  const std::size_t no = mesh.num_owned;
  PetscScalar* x = nullptr;
  DESCENT_PETSC_CHECK(VecGetArray(coordinates_, &x));
  for (std::size_t k = 0; k < 3 * no; ++k) x[k] = q ? double(q[k]) : mesh.rest_positions[k];
  DESCENT_PETSC_CHECK(VecRestoreArray(coordinates_, &x));
  MatNullSpace rigid = nullptr;
  DESCENT_PETSC_CHECK(MatNullSpaceCreateRigidBody(coordinates_, &rigid));
  DESCENT_PETSC_CHECK(MatSetNearNullSpace(matrix_, rigid));
  DESCENT_PETSC_CHECK(MatNullSpaceDestroy(&rigid));
}

template <class Real>
void AssembledHessian<Real>::to_local(const double* owned, Real* local) {
  const LocalMesh& mesh = problem_.mesh();
  const std::size_t no = mesh.num_owned, nv = mesh.num_vertices();
  std::fill(exchange_.begin(), exchange_.end(), 0.0);
  std::copy(owned, owned + 3 * no, exchange_.begin());
  halo_->sum(exchange_.data(), 3);
  for (std::size_t k = 0; k < 3 * nv; ++k) local[k] = static_cast<Real>(exchange_[k]);
}

template class AssembledHessian<double>;
template class AssembledHessian<float>;

}  // namespace descent

#endif
