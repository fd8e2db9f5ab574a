#pragma once
// The Hessian of eps as a distributed PETSc matrix: what Newton's PETSc solver
// (newton_petsc.hpp) and the petsc_gamg preconditioner
// (preconditioners/petsc_gamg.hpp) both factor or precondition. Includes
// PETSc: only for .cpp files compiled under DESCENT_HAVE_PETSC.
//
// Layout. PETSc's rows follow our ownership: rank r owns the 3 dofs of each
// of its owned vertices (LocalMesh: local ids [0, num_owned)), numbered
// contiguously from offset_r = sum over ranks s < r of 3 num_owned_s, dof
// 3 v + i of owned local vertex v at PETSc row offset_r + 3 v + i. Shared
// vertices owned elsewhere learn their owner's numbers once, through a
// Halo<double> sum in which only the owner contributes (so the sum is the
// owner's value exactly). Block size 3 (one block per vertex).
//
// Values. Every tet lies on one rank, which adds its 12x12 element Hessian
// (HessianOperator::element_hessians, corner order = the tet's 4 vertices x
// xyz) with global indices; rows owned by another rank travel through PETSc's
// stash at assembly. Each owner adds its owned dofs' vertex curvature
// m (1/h^2 + c/h) once. Held dofs get an identity row and column (entries
// coupling them stay in the pattern as explicit zeros). The pattern is fixed
// in the constructor (MATPREALLOCATOR: exact preallocation including
// off-rank contributions) and every assembly refills the same matrix
// (MatZeroEntries, add, assemble).
//
// Near null space: the six rigid-body modes of given positions
// (MatNullSpaceCreateRigidBody), which GAMG needs for elasticity.
//
// Communicator: MPI_COMM_WORLD (PETSc's world) when the mesh spans several
// ranks, MPI_COMM_SELF for a one-rank mesh.
#include <petscmat.h>

#include <memory>
#include <string>
#include <vector>

#include "comm/halo.hpp"
#include "solver/local_problem.hpp"
#include "solver/methods/hessian_operator.hpp"

namespace descent {

// Throws Error "file:line: what: call failed with PETSc error code" when
// code is not 0; `what` names the scene key whose solver made the call.
void check_petsc(PetscErrorCode code, const std::string& what, const char* call, const char* file,
                 int line);
#define DESCENT_PETSC_CALL(what, call) \
  ::descent::check_petsc((call), (what), #call, __FILE__, __LINE__)

template <class Real>
class AssembledHessian {
 public:
  // Fixes the pattern and the vertex curvature (from `hessian`, which is
  // read again by every assemble()). Collective (PETSc's, and one halo
  // exchange). `what` names the scene key, for errors.
  AssembledHessian(const LocalProblem<Real>& problem, const HessianOperator<Real>& hessian,
                   std::string what);
  ~AssembledHessian();
  AssembledHessian(const AssembledHessian&) = delete;
  AssembledHessian& operator=(const AssembledHessian&) = delete;

  MPI_Comm comm() const { return comm_; }
  Mat matrix() const { return matrix_; }

  // Refills the matrix from the element Hessians last stored by
  // hessian.assemble plus the vertex curvature. Collective.
  void assemble();
  // Attaches the rigid-body modes of positions q (3 reals per local vertex;
  // the rest positions when null) as the matrix's near null space. Collective.
  void set_rigid_body_modes(const Real* q);
  // Owned values (3 doubles per owned vertex, in PETSc's row order) to every
  // local vertex: shared ones from their owner through the halo, so all
  // sharers hold bitwise equal values.
  void to_local(const double* owned, Real* local);

 private:
  const LocalProblem<Real>& problem_;
  const HessianOperator<Real>& hessian_;
  std::string what_;
  MPI_Comm comm_ = MPI_COMM_NULL;
  std::unique_ptr<Halo<double>> halo_;  // shared vertices' values from their owner
  Mat matrix_ = nullptr;
  Vec coordinates_ = nullptr;
  std::vector<PetscInt> block_;        // per local vertex: PETSc block (vertex) index
  std::vector<PetscScalar> diagonal_;  // per owned dof: curvature, 1 on held dofs
  std::vector<double> exchange_;       // 3 per local vertex
};

}  // namespace descent
