#pragma once
// A scene: what to simulate and how, read from a TOML file plus command-line
// overrides. Every key has a default here; an unknown key or a value of the
// wrong type is an InputError naming the key (and the file and line).
#include <array>
#include <string>
#include <vector>

#include "meshes/generators.hpp"

namespace descent {

struct MeshSpec {
  std::string generator;  // "double_helix" or "box"; empty when `file` is set
  std::string file;       // .msh (Gmsh 2.2/4.1), .mesh (MEDIT), .node/.ele (TetGen)
  double scale = 1.0;     // applied to file coordinates (files have no units)
  DoubleHelixParams helix;
  BoxParams box;
};

struct MaterialSpec {
  std::string model = "neo_hookean";
  double young = 1.0e5;  // Pa
  double poisson = 0.3;
  double density = 1000;  // kg/m^3
};

// Vertices inside [box_min, box_max] (inclusive) are held at their rest
// position along each axis listed in `axes` ("xyz", "y", "xz", ...).
struct FixedRegion {
  std::array<double, 3> box_min{};
  std::array<double, 3> box_max{};
  std::string axes = "xyz";

  bool contains(const double* p) const {
    for (int i = 0; i < 3; ++i)
      if (p[i] < box_min[i] || p[i] > box_max[i]) return false;
    return true;
  }
};

struct TimeSpec {
  double dt = 1.0 / 30.0;  // s
  int frames = 60;
};

// Parameters of DESIGN §1's descent iteration (paper 1, §4).
struct SolverSpec {
  std::string method = "chebyshev";
  int iterations = 96;        // per time step
  double rho = 0.96;          // Chebyshev spectral-radius estimate
  int chebyshev_delay = 10;   // S: plain iterations before Chebyshev starts
  int hessian_interval = 32;  // M: Hessian diagonal re-evaluated every M iterations
  int check_interval = 8;     // energy check (the one allreduce) every 8 iterations
  double gamma = 0.7;         // step shrink factor on a failed check
  double alpha_max = 1.0;
  double alpha_min = 1.0e-3;
  std::string init = "constant_acceleration";  // "position", "velocity", "constant_acceleration"
  double eta = 0.2;      // weight of the acceleration term in that initialisation
  double damping = 0.0;  // air damping c (1/s), Eq. 20
};

struct OutputSpec {
  std::string dir = "out";
  int every = 1;  // write every n-th frame
};

struct Scene {
  std::string source;  // file the scene was read from, for messages
  MeshSpec mesh;
  MaterialSpec material;
  std::array<double, 3> gravity{0.0, -9.81, 0.0};
  std::vector<FixedRegion> fixed;
  TimeSpec time;
  SolverSpec solver;
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
