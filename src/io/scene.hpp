#pragma once
// A scene: what to simulate and how, read from a TOML file plus command-line
// overrides. Every key has a default here; an unknown key or a value of the
// wrong type is an InputError naming the key (and the file and line).
#include <array>
#include <string>
#include <vector>

#include "meshes/generators.hpp"
#include "partition/partition_spec.hpp"

namespace descent {

struct MeshSpec {
  std::string generator;  // "double_helix", "box", "ball" or "car"; empty when `file` is set
  std::string
      file;  // .h5 (read in parallel), .msh (Gmsh 2.2/4.1), .mesh (MEDIT), .node/.ele (TetGen)
  double scale = 1.0;  // applied to file coordinates (files have no units)
  DoubleHelixParams helix;
  BoxParams box;
  BallParams ball;
  CarParams car;
};

// One body of a scene with several ([[body]]): its mesh, placed by `scale`,
// then a rotation of `rotate_degrees` about `rotate_axis`, both about the
// body's rest centroid c (its centre of volume), then `translate`:
//   x = c + translate + Rot(axis, degrees) (scale (X - c)).
// It starts with the rigid velocity v(x) = velocity + angular_velocity x
// (x - c'), c' its placed centroid. `young` and `density` (0: [material]'s)
// override the scene's: young scales every modulus of the model (the whole
// energy density) by young / material.young; the model and the Poisson ratio
// are the scene's.
struct Body {
  MeshSpec mesh;             // file or generator (mesh.scale stays 1: `scale` is about c)
  std::string helix_preset;  // generator.helix.preset: a named resolution
  double scale = 1.0;
  std::array<double, 3> rotate_axis{0.0, 1.0, 0.0};
  double rotate_degrees = 0;
  std::array<double, 3> translate{};         // m
  std::array<double, 3> velocity{};          // m/s
  std::array<double, 3> angular_velocity{};  // rad/s, about c' (right-handed)
  double young = 0;                          // Pa
  double density = 0;                        // kg/m^3
};

// Invertible model conversion (paper 1, Eqs. 17-19): per element an
// interpolant l in [0, 1] toward the `arap` energy, driven by the smallest
// signed singular value of F between lambda_minus and lambda_plus, decaying
// by at most `decay` (L) per iteration.
struct ConversionSpec {
  bool enabled = false;
  double lambda_minus = 0.05;
  double lambda_plus = 0.15;
  double decay = 0.05;
};

struct MaterialSpec {
  // stvk, neo_hookean, mooney_rivlin, fung, corotated, arap (DESIGN §1)
  std::string model = "neo_hookean";
  double young = 1.0e5;  // Pa
  double poisson = 0.3;
  double density = 1000;  // kg/m^3
  double c2 = 0;          // Pa: mooney_rivlin and fung
  double c3 = 0;          // fung's exponential rate
  ConversionSpec conversion;
};

// Whether point p (xyz) lies in the closed box [lo, hi].
inline bool in_box(const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                   const double* p) {
  for (int i = 0; i < 3; ++i)
    if (p[i] < lo[i] || p[i] > hi[i]) return false;
  return true;
}

// Prescribed motion of a fixed region as a function of time t, applied to
// the held axes of its vertices; the motion stops at t = `until`:
//   translate: x(t) = X + velocity * min(t, until)
//   rotate:    x(t) = centre + Rot(axis, angular_velocity * min(t, until)) (X - centre)
struct Motion {
  std::string kind = "none";                  // none, translate, rotate
  std::array<double, 3> velocity{};           // m/s
  std::array<double, 3> axis{0.0, 1.0, 0.0};  // rotation axis (normalised on use)
  std::array<double, 3> centre{};             // a point on the rotation axis
  double angular_velocity = 0;                // rad/s
  double until = 1e300;                       // s
};

// Vertices inside [box_min, box_max] (inclusive) are held along each axis
// listed in `axes` ("xyz", "y", "xz", ...): at their rest position, or moved
// by `motion`.
struct FixedRegion {
  std::array<double, 3> box_min{};
  std::array<double, 3> box_max{};
  std::string axes = "xyz";
  Motion motion;

  bool contains(const double* p) const { return in_box(box_min, box_max, p); }
};

// A surface load: the total force `force` spread over the boundary faces
// whose three vertices lie in [box_min, box_max], by face area (each face
// gives a third of its share to each of its vertices). It grows linearly from
// zero to `force` over the first `ramp` seconds (0: applied at once).
struct LoadRegion {
  std::array<double, 3> box_min{};
  std::array<double, 3> box_max{};
  std::array<double, 3> force{};  // N
  double ramp = 0;                // s

  bool contains(const double* p) const { return in_box(box_min, box_max, p); }
};

// A rigid obstacle ([[obstacle]]) the body may touch but not enter:
//   plane:  the half-space behind `point` along -`normal` is solid
//   sphere: the ball of `radius` about `centre`
//   box:    the box [box_min, box_max] is solid
// `motion` moves it rigidly (as it moves a fixed region: translate by
// velocity t, or rotate about centre and axis) until `motion.until`.
// `friction` is the Coulomb coefficient between it and the body.
struct Obstacle {
  std::string kind = "plane";  // plane, sphere, box
  std::array<double, 3> point{};
  std::array<double, 3> normal{0.0, 1.0, 0.0};
  std::array<double, 3> centre{};
  double radius = 0;
  std::array<double, 3> box_min{};
  std::array<double, 3> box_max{};
  double friction = 0;
  Motion motion;
};

// How the body and the obstacles keep apart (docs/contact.md).
struct ContactSpec {
  // "energy": a barrier in eps, active below `distance`, with lagged
  // friction (paper 1, Sec. 8's repulsive potential; IPC's barrier);
  // "projection": vertices inside an obstacle are moved out at the end of
  // each step and their velocity updated (paper 2's collision pass).
  std::string method = "energy";
  // Activation distance d_hat of the barrier (m); 0: 1e-3 of the diagonal
  // of the body's bounding box.
  double distance = 0;
  // Barrier stiffness kappa (N/m); 0: per vertex, the stiffness its mass and
  // the elasticity around it give it (m/h^2 plus the rest Hessian diagonal).
  double stiffness = 0;
  // Lagged friction's smoothing velocity eps_v (m/s): slower relative
  // sliding is resisted elastically (static friction's creep).
  double smoothing_velocity = 1.0e-3;
  // Contact of a body with itself (surface pairs within one body), besides
  // the contact between bodies that a scene of several bodies has.
  bool self = false;
  // The Coulomb coefficient of friction between bodies (and within one).
  double friction = 0;
};

struct TimeSpec {
  double dt = 1.0 / 30.0;  // s
  int frames = 60;
  // No inertia (and no damping): each frame is a static equilibrium under
  // the loads and motions at its time.
  bool quasistatic = false;
};

// What a scene's Chebyshev step runs to when the scene sets neither
// solver.accuracy nor solver.iterations: a fixed count left an untuned scene
// (a Mooney-Rivlin dragon) at errors of 0.6-0.8 a step. The study's metric,
// as jobs/helix.toml sets it.
constexpr double kDefaultAccuracy = 1e-2;
// The cap on a step that runs to an accuracy, where the scene gives no
// `iterations`: the jobs' cap, above the 240-310 iterations Jacobi's D^-1
// takes on the helix at 1e-2, so that the target, not the cap, ends a step.
constexpr int kDefaultAccuracyCap = 1000;

// Parameters of DESIGN §1's descent iteration (paper 1, §4).
struct SolverSpec {
  // "chebyshev", "gd", "jacobi_gd", "nesterov", "ncg", "lbfgs", "newton",
  // "pd_chebyshev", "linear_cg" (docs/methods.md), and PETSc TAO's "tao_bncg"
  // and "tao_blmvm" (docs/tao.md; builds with PETSc only).
  std::string method = "chebyshev";
  // "auto": alpha and rho from an estimate of the spectrum of D^-1 H
  // (solver/spectrum.hpp), made online and reused; "fixed": rho, alpha_max,
  // chebyshev_delay and the phases as given (paper 1's method). A scene
  // that sets rho, phase_rho or alpha_max gets "fixed" unless it says.
  std::string chebyshev_parameters = "auto";
  int iterations = 96;  // per time step (with accuracy: the cap)
  // Target relative error e of each step (the study's metric); 0: run
  // `iterations`. Chebyshev chooses the count from its error bound and the
  // energy checks, the other descent methods from the energy checks, Newton
  // from its decrement, linear_cg from its residual (docs/methods.md). A
  // scene read from TOML that sets neither key runs Chebyshev to
  // kDefaultAccuracy (resolve_step_accuracy, scene_checks.hpp).
  double accuracy = 0;
  // The automatic parameters: Lanczos steps per estimate, steps between
  // estimates (0: only after a rollback), and the margin above the
  // estimated largest eigenvalue (b = (1 + margin) lambda_max).
  int spectrum_steps = 20;
  int spectrum_interval = 20;
  double spectrum_margin = 0.1;
  double rho = 0.96;          // Chebyshev spectral-radius estimate (fixed parameters)
  int chebyshev_delay = 10;   // S: plain iterations before Chebyshev starts (fixed parameters)
  int hessian_interval = 32;  // M: Hessian diagonal re-evaluated every M iterations
  int check_interval = 8;     // energy check (the one allreduce) every 8 iterations
  double gamma = 0.7;         // step shrink factor on a failed check
  double alpha_max = 1.0;
  double alpha_min = 1.0e-3;
  // "position", "velocity", "constant_acceleration", "optimized" (Eq. 10:
  // one more MPI_Allreduce per step)
  std::string init = "constant_acceleration";
  double eta = 0.2;      // weight of the acceleration term in that initialisation
  double damping = 0.0;  // air damping c (1/s), Eq. 20
  // Chebyshev phases (paper 1, §4.3; solver/methods/chebyshev_phases.hpp):
  // rho per phase and the lengths of all but the last; empty: one phase, rho.
  std::vector<double> phase_rho;
  std::vector<int> phase_lengths;
  int history = 5;  // lbfgs: pairs (s, y) kept
  // newton: stop at |grad| <= newton_tolerance |grad(q0)| or after
  // newton_iterations; each linear solve (PCG) to |r| <= cg_tolerance |b|.
  double newton_tolerance = 1e-10;
  // "fallback": exact element Hessians, the PSD-projected ones for any Newton
  // iteration whose exact system is not positive definite along CG's path or
  // gives no descent; "always": projected throughout (linear convergence
  // wherever an element's exact Hessian is indefinite at the solution).
  std::string newton_projection = "fallback";
  int newton_iterations = 50;
  double cg_tolerance = 1e-10;
  int cg_iterations = 20000;
  // newton's linear solver: "cg" (the PCG above, distributed), "ldlt"
  // (Eigen's sparse LDL^T of the assembled Hessian, gathered on rank 0) or
  // "petsc" (the assembled Hessian as a distributed PETSc matrix, CG with
  // algebraic multigrid; builds with PETSc only).
  std::string newton_solver = "cg";
  // PETSc options for the PETSc solvers, e.g. "-pc_type hypre -ksp_monitor",
  // after those of PETSC_OPTIONS and --petsc-options.
  std::string petsc_options;
  // linear_cg (paper 2; solver/methods/linear_cg.hpp): linearly implicit
  // Euler (M(1 + h c) + (h^2 + h beta) K) v = M v_t + h (f_el + f_ext) with
  // the corotated stiffness K, solved by PCG for at most `iterations`
  // iterations or until r.r <= linear_cg_tolerance b.b.
  std::string linear_cg_guess = "velocity";         // "zero", "velocity", "euler" (v_t + h M^-1 f)
  std::string linear_cg_preconditioner = "jacobi";  // "identity", "mass", "jacobi"
  double linear_cg_tolerance = 1e-10;
  int polar_sweeps = 4;             // 2x2 Jacobi sweeps of the polar decomposition, at most
  double rayleigh_stiffness = 0.0;  // beta (s): stiffness-proportional Rayleigh damping
  // P^-1 of the methods that precondition (solver/preconditioners/): "jacobi",
  // "multilevel", "petsc_gamg" (builds with PETSc) or "auto" (the default):
  // multilevel for chebyshev with its automatic parameters (faster to every
  // accuracy on the main job and the study scenes: bench/results/multilevel)
  // on the CPU and for newton's CG (16-18x per Newton step on the helix:
  // bench/results/newton_step), for a body with inertia or held dofs and
  // (chebyshev) without contact between bodies; jacobi for every other method (the
  // papers' forms), for the fixed parameters (tuned to Jacobi's spectrum),
  // on a device, and for a quasi-static body nothing holds.
  // preconditioner_of() resolves it by method (multilevel_fits() and
  // ChebyshevDescent the rest).
  std::string preconditioner = "auto";
  // Steps between rebuilds of a multilevel P^-1 at the step's start (1: every
  // step); a rollback always rebuilds it.
  int preconditioner_refresh = 1;
  // The multilevel hierarchy (solver/preconditioners/multilevel/): the edge
  // of the coarse grid whose cells aggregate the vertices of the finest level,
  // in mean edge lengths of the mesh (doubled at each coarser level), the
  // degree of the Chebyshev-Jacobi smoother before and after each coarse
  // correction, and the unknowns at most of the coarsest level, solved exactly.
  double multilevel_cell = 3.0;
  int multilevel_smoother_degree = 2;
  int multilevel_coarse_size = 2000;
};

// The preconditioner `spec` applies: solver.preconditioner, with "auto"
// resolved for spec's method.
inline std::string preconditioner_of(const SolverSpec& spec) {
  if (spec.preconditioner != "auto") return spec.preconditioner;
  const bool chebyshev = spec.method == "chebyshev" && spec.chebyshev_parameters == "auto";
  const bool newton_cg = spec.method == "newton" && spec.newton_solver == "cg";
  return chebyshev || newton_cg ? "multilevel" : "jacobi";
}

struct OutputSpec {
  std::string dir = "out";
  int every = 1;  // write every n-th frame
  // Write a checkpoint (for --restart) every n-th frame and after the last;
  // 0: never.
  int checkpoint_every = 10;
};

struct Scene {
  std::string source;        // file the scene was read from, for messages
  MeshSpec mesh;             // the one body of a scene without [[body]]
  std::vector<Body> bodies;  // [[body]]: several bodies, one mesh (no [mesh])
  MaterialSpec material;
  std::array<double, 3> gravity{0.0, -9.81, 0.0};
  std::vector<FixedRegion> fixed;
  std::vector<LoadRegion> loads;    // [[load]]
  std::vector<Obstacle> obstacles;  // [[obstacle]]
  ContactSpec contact;
  TimeSpec time;
  SolverSpec solver;
  PartitionSpec partition;
  OutputSpec output;
};

// Reads `path` and applies each "key=value" override (value in TOML syntax,
// e.g. "solver.iterations=64", "gravity=[0,0,-9.81]", "mesh.file=\"a.msh\"")
// before validation, so an override is checked exactly like a file entry.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

// The same from TOML text already in memory; `source` names it in messages.
Scene parse_scene(const std::string& toml_text, const std::string& source,
                  const std::vector<std::string>& overrides = {});

}  // namespace descent
