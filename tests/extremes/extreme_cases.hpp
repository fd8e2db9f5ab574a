#pragma once
// The cases of the extremes suite (issue 6), built in code so the fast ctest
// subset (test_extremes.cpp) and the full sweep (extremes_driver.cpp, run by
// jobs/extremes/sweep.py) run the very same scenes. docs/extremes.md
// describes each case and why it is extreme.
#include <array>
#include <string>
#include <vector>

#include "common/mesh.hpp"
#include "io/scene.hpp"

namespace descent::extremes {

// How the body starts: at rest in its rest shape, with every vertex
// uniformly random in the rest bounding box, or with every vertex at the
// box's centre.
enum class Start { rest, random, collapsed };

struct Case {
  std::string name;   // e.g. "dt_1", "E_1e11", "stretch_5x"
  std::string group;  // "time step", "stiffness", "deformation", ...
  std::string what;   // one line for the table
  Scene scene;        // material model, conversion, solver, time, fixed regions
  Mesh mesh;          // the global mesh (generators, or a box with a glued bad tet)
  int frames = 10;
  Start start = Start::rest;
  // Initial velocity of every vertex (held axes ignore it), m/s.
  std::array<double, 3> velocity{0.0, 0.0, 0.0};
  // The rest shape must come back (random and collapsed starts): the
  // distance reported is then max |sigma - 1| over the tets, not a reference.
  bool recovers = false;
};

// Every case name of the full sweep, in table order.
std::vector<std::string> case_names();

// Models of the suite (DESIGN §1): every case runs each of them.
const std::vector<std::string>& model_names();

// The case `name` with `model` (mooney_rivlin and fung get c2 = E / 20, fung
// c3 = 2). Throws InputError for an unknown case or model.
Case make_case(const std::string& name, const std::string& model);

// Positions where a case starts (xyz by global vertex id).
std::vector<double> start_positions(const Case& c);

}  // namespace descent::extremes
