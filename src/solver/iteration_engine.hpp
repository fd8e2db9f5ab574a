#pragma once
// Where the Chebyshev iteration runs (DESIGN §4): one rank's mesh, iterates
// and iteration in an execution's memory, driven by the one Chebyshev
// stepper (solver/chebyshev_descent.hpp) on every backend. One template over
// an execution (solver/iteration_engine_impl.hpp): the host (OpenMP), always
// built and the engine of every CPU run, and CUDA, built when a CUDA compiler
// is found. The stepper does not know which one it drives.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "comm/halo.hpp"
#include "comm/reduction.hpp"
#include "io/scene.hpp"
#include "solver/local_problem.hpp"
#include "solver/preconditioners/preconditioner.hpp"

namespace descent {

// How element results reach vertices: gather sums each vertex's corners from
// a vertex -> (tet, corner) table in a fixed order (deterministic, the
// default); scatter adds them atomically (less memory traffic, order not fixed).
enum class Assembly { gather, scatter };
const char* to_string(Assembly assembly);

struct EngineOptions {
  Assembly assembly = Assembly::gather;
  // Replay the iterations between two energy checks as one captured graph
  // (where there is no exchange in between: a rank without neighbours).
  bool graphs = true;
  int device = 0;  // CUDA device ordinal
};

// Memory the engine allocated, split by what it scales with (on the host
// the mesh data the problem already holds is used in place, not counted).
struct EngineMemory {
  std::size_t tet_bytes = 0;     // arrays with an entry per tet
  std::size_t vertex_bytes = 0;  // arrays with an entry per vertex
  std::size_t other_bytes = 0;   // fixed-size: parameters, reduction scratch
  std::size_t total() const { return tet_bytes + vertex_bytes + other_bytes; }
};

template <class Real>
class IterationEngine {
 public:
  virtual ~IterationEngine() = default;

  // Host buffers (pinned on a device), 3 reals per local vertex each,
  // through which a step's data travel: the stepper writes the initial guess
  // q, inertial target y, step-start positions qt and the external force
  // there, and download() fills q. `vector` carries a Lanczos start vector.
  struct Staging {
    Real* q;
    Real* y;
    Real* qt;
    Real* force;
    Real* vector;
  };
  virtual Staging staging() = 0;
  // A step's start: the staged q (also the checked and the previous
  // iterate), y, qt, the force when `upload_force` (else the last one stays),
  // and with conversion the interpolants (one per tet; ignored otherwise).
  virtual void begin_step(bool upload_force, const Real* interpolants) = 0;
  // `count` iterations from the current iterate. Iteration i re-evaluates
  // the Hessian diagonal when refresh[i] != 0 and uses alpha[i], omega[i].
  virtual void iterate(int count, const std::uint8_t* refresh, const Real* alpha,
                       const Real* omega) = 0;
  // This rank's share of eps at the current (or the last checked) iterate.
  virtual Energy local_energy(bool checked) = 0;
  // checked <- current.
  virtual void accept() = 0;
  // current, previous <- checked (Chebyshev restarts from there).
  virtual void rollback() = 0;
  // With contact between bodies: whether a surface vertex of the current
  // iterate has drifted far enough from where its pairs were found that they
  // must be found again (BodyContact::needs_rebuild); false without.
  virtual bool contact_pairs_drifted() = 0;
  // Collective with contact between bodies: its pairs found again about the
  // current iterate (BodyContact::rebuild_here); nothing without.
  virtual void refresh_contact_pairs() = 0;
  // The current (or checked) iterate into staging().q.
  virtual void download(bool checked) = 0;
  virtual void download_interpolants(Real* interpolants) = 0;

  // Replaces the Jacobi diagonal D^-1 of the iterations by the preconditioner
  // solver.preconditioner names (not "jacobi"), on the engine's execution:
  // each iteration then forms the gradient g, applies P^-1 and updates along
  // -alpha P^-1 g; no diagonal is refreshed. Collective.
  virtual void use_preconditioner(const SolverSpec& spec) = 0;
  // Null while the iterations use D^-1.
  virtual const Preconditioner<Real>* preconditioner() const = 0;
  // P^-1 rebuilt at the current iterate. Collective.
  virtual void refresh_preconditioner() = 0;

  // The spectrum estimate (solver/spectrum.hpp): Lanczos on P^-1 H at the
  // current iterate, H the exact Hessian of eps (held dofs removed), P^-1
  // the iterations' preconditioner (D^-1: the diagonal they use). Vectors
  // live in the engine: with D^-1 v (the current Lanczos vector), v_prev and
  // w in the D inner product; with another P^-1 the residual-space vectors
  // beside them, in the P inner product (as in PCG: s, z = P^-1 s, s . z).
  // Sums are this rank's, over owned dofs; the caller reduces them (one
  // counted allreduce each).
  // The diagonal at the current iterate, as the next refreshing iteration
  // would compute it (that iteration may then skip its refresh).
  virtual void refresh_diagonal() = 0;
  // Per axis: the sums over owned free dofs of that axis of the vertex
  // curvature m (1/h^2 + c/h) and of the diagonal ([2 axis], [2 axis + 1]):
  // the Rayleigh quotient of a rigid translation without its (boundary)
  // strain, an estimate of the bottom of D^-1 H's spectrum (0 with another
  // preconditioner: no quotient of it is at hand).
  virtual std::array<double, 6> translation_sums() = 0;
  // w <- staging().vector on free dofs (0 on held ones), v = v_prev = 0;
  // returns w . D w (with P^-1: s <- the staged vector, z = P^-1 s; s . z).
  virtual double lanczos_begin() = 0;
  // v_prev <- v, v <- w / beta (with P^-1: u_prev <- u, u <- s / beta,
  // v <- z / beta).
  virtual void lanczos_next(double beta) = 0;
  // y <- H v; returns v . H v.
  virtual double lanczos_product() = 0;
  // w <- D^-1 y - alpha v - beta_prev v_prev; returns w . D w (with P^-1:
  // s <- y - alpha u - beta_prev u_prev, z = P^-1 s; s . z).
  virtual double lanczos_orthogonalize(double alpha, double beta_prev) = 0;

  // The host waits for all queued work.
  virtual void synchronize() = 0;

  // The element pass alone over all tets (gradient, and the Hessian diagonal
  // when with_diag), `repeats` launches back to back: seconds per pass, and
  // the bytes one pass requests from memory (tet ids, rest data, the four
  // corners' positions per tet, and its outputs), for a bandwidth figure.
  struct KernelTiming {
    double seconds = 0;
    double bytes = 0;
  };
  virtual KernelTiming time_element_pass(bool with_diag, int repeats) = 0;

  virtual EngineMemory memory() const = 0;
  virtual std::string describe() const = 0;
  // Whether the engine's memory is a device's (the CPU stepper needs no
  // report of it).
  virtual bool on_device() const = 0;
  // Captured sequences replayed so far (0 where nothing is captured).
  virtual long graph_launches() const = 0;
};

// The host engine (OpenMP): every CPU run's; `halo` is the rank's exchange
// of shared-vertex partial sums.
template <class Real>
std::unique_ptr<IterationEngine<Real>> make_host_engine(LocalProblem<Real>& problem,
                                                        Halo<Real>& halo,
                                                        const EngineOptions& options);
// The CUDA engine on device options.device; a build without CUDA throws
// InputError saying so.
template <class Real>
std::unique_ptr<IterationEngine<Real>> make_cuda_engine(LocalProblem<Real>& problem,
                                                        Halo<Real>& halo,
                                                        const EngineOptions& options);

}  // namespace descent
