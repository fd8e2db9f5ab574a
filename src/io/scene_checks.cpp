#include "io/scene_checks.hpp"

#include <algorithm>
#include <array>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/error.hpp"

namespace descent {

namespace {

void require(const SceneDocument& doc, bool holds, std::string_view key, std::string_view rule,
             double value) {
  if (holds) return;
  throw InputError(
      detail::concat(doc.where(key), ": ", key, " must be ", rule, ", got ", format_number(value)));
}

void require_one_of(const SceneDocument& doc, std::string_view key, const std::string& value,
                    std::initializer_list<std::string_view> choices) {
  if (std::find(choices.begin(), choices.end(), value) != choices.end()) return;
  std::string listed;
  for (std::string_view choice : choices) {
    listed += (listed.empty() ? "\"" : ", \"") + std::string(choice) + "\"";
  }
  throw InputError(detail::concat(doc.where(key), ": ", key, " must be one of ", listed, ", got \"",
                                  value, "\""));
}

// A non-empty subset of "xyz", each axis at most once.
bool is_axis_set(const std::string& axes) {
  if (axes.empty()) return false;
  for (std::size_t i = 0; i < axes.size(); ++i) {
    if (std::string_view("xyz").find(axes[i]) == std::string_view::npos) return false;
    if (axes.find(axes[i], i + 1) != std::string::npos) return false;
  }
  return true;
}

// box_min <= box_max along each axis, for the region at `prefix`
// ("fixed.0.", "load.2.").
void check_box_order(const SceneDocument& doc, const std::string& prefix,
                     const std::array<double, 3>& box_min, const std::array<double, 3>& box_max) {
  for (std::size_t axis = 0; axis < 3; ++axis) {
    if (box_min[axis] > box_max[axis]) {
      const std::string key = prefix + "box_min";
      throw InputError(detail::concat(
          doc.where(key), ": ", key, " must not exceed ", prefix, "box_max, but its ", "xyz"[axis],
          " is ", format_number(box_min[axis]), " > ", format_number(box_max[axis])));
    }
  }
}

void check_motion(const SceneDocument& doc, const Motion& motion, const std::string& prefix) {
  require_one_of(doc, prefix + "kind", motion.kind, {"none", "translate", "rotate"});
  // A zero axis has no direction to normalise; it only matters for a rotation.
  const bool zero_axis = motion.axis == std::array<double, 3>{};
  if (motion.kind == "rotate" && zero_axis) {
    const std::string key = prefix + "axis";
    throw InputError(detail::concat(doc.where(key), ": ", key, " must not be [0, 0, 0] when ",
                                    prefix, "kind is \"rotate\""));
  }
  require(doc, motion.until >= 0, prefix + "until", ">= 0", motion.until);
}

// The generator keys of a mesh source, by their names in the scene: [mesh]'s
// ("mesh.generator", "mesh.helix", ...) or a [[body]]'s ("body.0.generator.kind",
// "body.0.generator.helix", ...).
struct MeshKeys {
  std::string owner;      // what needs the mesh: "the scene", "body.0"
  std::string table;      // "mesh", "body.0"
  std::string file;       // "mesh.file"
  std::string generator;  // "mesh.generator"
  std::string helix;      // "mesh.helix": its keys are helix + ".resolution", ...
  std::string box;        // "mesh.box"
  std::string ball;       // "mesh.ball"
  std::string car;        // "mesh.car"
};

MeshKeys scene_mesh_keys() {
  return {"the scene",  "mesh",     "mesh.file", "mesh.generator",
          "mesh.helix", "mesh.box", "mesh.ball", "mesh.car"};
}

// `body` names the table: "body.0".
MeshKeys body_mesh_keys(const std::string& body) {
  return {body,
          body,
          body + ".file",
          body + ".generator.kind",
          body + ".generator.helix",
          body + ".generator.box",
          body + ".generator.ball",
          body + ".generator.car"};
}

void check_helix(const SceneDocument& doc, const DoubleHelixParams& helix, const MeshKeys& keys) {
  const std::string at = keys.helix + ".";
  require(doc, helix.resolution > 0, at + "resolution", "> 0", helix.resolution);
  require(doc, helix.helix_radius > 0, at + "helix_radius", "> 0", helix.helix_radius);
  require(doc, helix.tube_radius > 0, at + "tube_radius", "> 0", helix.tube_radius);
  require(doc, helix.pitch > 0, at + "pitch", "> 0", helix.pitch);
  require(doc, helix.turns > 0, at + "turns", "> 0", helix.turns);
}

void check_box(const SceneDocument& doc, const BoxParams& box, const MeshKeys& keys) {
  const std::string at = keys.box + ".";
  for (std::size_t axis = 0; axis < 3; ++axis) {
    require(doc, box.cells[axis] >= 1, at + "cells", "at least 1 along each axis", box.cells[axis]);
    require(doc, box.size[axis] > 0, at + "size", "> 0 along each axis", box.size[axis]);
  }
  require(doc, box.tets_per_cell == 5 || box.tets_per_cell == 6, at + "tets_per_cell", "5 or 6",
          box.tets_per_cell);
}

void check_ball(const SceneDocument& doc, const BallParams& ball, const MeshKeys& keys) {
  const std::string at = keys.ball + ".";
  require(doc, ball.cells >= 1 && ball.cells <= 1000, at + "cells", "in [1, 1000]", ball.cells);
  require(doc, ball.radius > 0, at + "radius", "> 0", ball.radius);
}

void check_car(const SceneDocument& doc, const CarParams& car, const MeshKeys& keys) {
  const std::string at = keys.car + ".";
  require(doc, car.cells >= 8 && car.cells <= 4000, at + "cells", "in [8, 4000]", car.cells);
  require(doc, car.length > 0, at + "length", "> 0", car.length);
  require(doc, car.width > 0, at + "width", "> 0", car.width);
  require(doc, car.height > 0, at + "height", "> 0", car.height);
}

void check_generator_values(const SceneDocument& doc, const MeshSpec& mesh, const MeshKeys& keys) {
  if (mesh.generator == "double_helix") check_helix(doc, mesh.helix, keys);
  if (mesh.generator == "box") check_box(doc, mesh.box, keys);
  if (mesh.generator == "ball") check_ball(doc, mesh.ball, keys);
  if (mesh.generator == "car") check_car(doc, mesh.car, keys);
}

// Exactly one of file and generator, a known generator, and the parameter
// table of that generator only.
void check_mesh_keys(const SceneDocument& doc, const MeshSpec& mesh, const MeshKeys& keys) {
  const bool has_generator = doc.has(keys.generator);
  const bool has_file = doc.has(keys.file);
  if (!has_generator && !has_file) {
    throw InputError(detail::concat(
        doc.where(keys.table), ": ", keys.owner, " needs a mesh: set ", keys.generator,
        " (\"double_helix\", \"box\", \"ball\" or \"car\") or ", keys.file));
  }
  if (has_generator && has_file) {
    throw InputError(detail::concat(doc.where(keys.file), ": ", keys.file, " and ", keys.generator,
                                    " exclude each other (", doc.where(keys.generator), " sets ",
                                    keys.generator, ")"));
  }
  if (has_file && mesh.file.empty()) {
    throw InputError(detail::concat(doc.where(keys.file), ": ", keys.file, " must not be empty"));
  }
  if (has_generator)
    require_one_of(doc, keys.generator, mesh.generator, {"double_helix", "box", "ball", "car"});
  // A parameter table of the other generator would be silently ignored.
  const std::string mesh_from =
      has_file ? detail::concat("the mesh is read from ", keys.file)
               : detail::concat(keys.generator, " is \"", mesh.generator, "\"");
  if (doc.has(keys.helix) && mesh.generator != "double_helix") {
    throw InputError(detail::concat(doc.where(keys.helix), ": ", keys.helix, " goes with ",
                                    keys.generator, " = \"double_helix\", but ", mesh_from));
  }
  if (doc.has(keys.box) && mesh.generator != "box") {
    throw InputError(detail::concat(doc.where(keys.box), ": ", keys.box, " goes with ",
                                    keys.generator, " = \"box\", but ", mesh_from));
  }
  if (doc.has(keys.ball) && mesh.generator != "ball") {
    throw InputError(detail::concat(doc.where(keys.ball), ": ", keys.ball, " goes with ",
                                    keys.generator, " = \"ball\", but ", mesh_from));
  }
  if (doc.has(keys.car) && mesh.generator != "car") {
    throw InputError(detail::concat(doc.where(keys.car), ": ", keys.car, " goes with ",
                                    keys.generator, " = \"car\", but ", mesh_from));
  }
}

// A preset (which conflicts with the resolution) sets the helix resolution.
void apply_preset(const SceneDocument& doc, const MeshKeys& keys, const std::string& preset,
                  DoubleHelixParams& helix) {
  const std::string preset_key = keys.helix + ".preset";
  const std::string resolution_key = keys.helix + ".resolution";
  if (!doc.has(preset_key)) return;
  if (doc.has(resolution_key)) {
    throw InputError(detail::concat(doc.where(resolution_key), ": ", resolution_key, " and ",
                                    preset_key,
                                    " exclude each other (a preset is a named resolution)"));
  }
  try {
    helix.resolution = double_helix_preset_resolution(preset);
  } catch (const InputError& error) {
    throw InputError(detail::concat(doc.where(preset_key), ": ", preset_key, ": ", error.what()));
  }
}

// A [[fixed]] table; `prefix` names it ("fixed.0.").
void check_entry(const SceneDocument& doc, const FixedRegion& region, const std::string& prefix) {
  if (!is_axis_set(region.axes)) {
    const std::string key = prefix + "axes";
    throw InputError(detail::concat(doc.where(key), ": ", key,
                                    " must name each of x, y, z at most once (\"xyz\", \"y\", "
                                    "\"xz\", ...), got \"",
                                    region.axes, "\""));
  }
  check_box_order(doc, prefix, region.box_min, region.box_max);
  check_motion(doc, region.motion, prefix + "motion.");
}

// A [[load]] table; `prefix` names it ("load.0.").
void check_entry(const SceneDocument& doc, const LoadRegion& region, const std::string& prefix) {
  check_box_order(doc, prefix, region.box_min, region.box_max);
  require(doc, region.ramp >= 0, prefix + "ramp", ">= 0", region.ramp);
}

// An [[obstacle]] table; `prefix` names it ("obstacle.0."). The keys of its
// shape are those of its kind only: a radius set on a plane would be
// silently ignored, so it is an error.
void check_entry(const SceneDocument& doc, const Obstacle& obstacle, const std::string& prefix) {
  require_one_of(doc, prefix + "kind", obstacle.kind, {"plane", "sphere", "box"});
  const std::initializer_list<std::pair<std::string_view, std::string_view>> shape_keys = {
      {"point", "plane"},   {"normal", "plane"}, {"centre", "sphere"},
      {"radius", "sphere"}, {"box_min", "box"},  {"box_max", "box"}};
  for (const auto& [key, kind] : shape_keys) {
    const std::string full = prefix + std::string(key);
    if (kind != obstacle.kind && doc.has(full))
      throw InputError(detail::concat(doc.where(full), ": ", full, " belongs to an obstacle of ",
                                      prefix, "kind = \"", kind, "\", but this one is \"",
                                      obstacle.kind, "\""));
  }
  if (obstacle.kind == "plane" && obstacle.normal == std::array<double, 3>{}) {
    const std::string key = prefix + "normal";
    throw InputError(detail::concat(doc.where(key), ": ", key,
                                    " must not be [0, 0, 0]: it says which side is solid"));
  }
  if (obstacle.kind == "sphere")
    require(doc, obstacle.radius > 0, prefix + "radius", "> 0", obstacle.radius);
  if (obstacle.kind == "box") {
    check_box_order(doc, prefix, obstacle.box_min, obstacle.box_max);
    for (std::size_t axis = 0; axis < 3; ++axis)
      if (obstacle.box_min[axis] == obstacle.box_max[axis]) {
        const std::string key = prefix + "box_max";
        throw InputError(detail::concat(doc.where(key), ": ", key, " must exceed ", prefix,
                                        "box_min along every axis (a solid box), but its ",
                                        "xyz"[axis], " equals it"));
      }
  }
  require(doc, obstacle.friction >= 0, prefix + "friction", ">= 0", obstacle.friction);
  check_motion(doc, obstacle.motion, prefix + "motion.");
}

// A [[body]] table; `prefix` names it ("body.0."). Its mesh source was
// checked by check_mesh_source.
void check_entry(const SceneDocument& doc, const Body& body, const std::string& prefix) {
  check_generator_values(doc, body.mesh, body_mesh_keys(prefix.substr(0, prefix.size() - 1)));
  require(doc, body.scale > 0, prefix + "scale", "> 0", body.scale);
  if (body.rotate_degrees != 0 && body.rotate_axis == std::array<double, 3>{}) {
    const std::string key = prefix + "rotate.axis";
    throw InputError(detail::concat(doc.where(key), ": ", key, " must not be [0, 0, 0] when ",
                                    prefix, "rotate.degrees is not 0"));
  }
  // 0 is the default (the scene's value); written in the scene, it must be a
  // material's.
  if (doc.has(prefix + "material.young"))
    require(doc, body.young > 0, prefix + "material.young", "> 0", body.young);
  if (doc.has(prefix + "material.density"))
    require(doc, body.density > 0, prefix + "material.density", "> 0", body.density);
}

void check_contact(const SceneDocument& doc, const Scene& scene) {
  const ContactSpec& contact = scene.contact;
  require_one_of(doc, "contact.method", contact.method, {"energy", "projection"});
  require(doc, contact.distance >= 0, "contact.distance", ">= 0 (0: from the body's size)",
          contact.distance);
  require(doc, contact.stiffness >= 0, "contact.stiffness", ">= 0 (0: from masses and material)",
          contact.stiffness);
  require(doc, contact.smoothing_velocity > 0, "contact.smoothing_velocity", "> 0",
          contact.smoothing_velocity);
  require(doc, contact.friction >= 0, "contact.friction", ">= 0", contact.friction);
  // The barriers live in eps; chebyshev and the first-order methods gd,
  // jacobi_gd, nesterov, ncg and lbfgs evaluate them and keep every iterate
  // (and nesterov's extrapolated points) outside, and so does newton (its CG
  // solve: the direct and PETSc solvers assemble no contact terms); the
  // others do not yet. Between bodies they need
  // Jacobi's D (no other preconditioner knows the pairs), and so do obstacles' with the methods
  // beyond chebyshev and newton (below). As a projection pass after the
  // solve contact takes any.
  if (contact.method != "energy") return;
  const bool between_bodies = scene.bodies.size() > 1 || contact.self;
  if (!between_bodies && scene.obstacles.empty()) return;
  const std::string what =
      contact.self     ? std::string("contact.self = true (contact between bodies)")
      : between_bodies ? std::string("a scene of several bodies ([[body]], contact between them)")
                       : std::string("obstacles ([[obstacle]])");
  const std::string& method = scene.solver.method;
  const bool evaluates_barrier = method == "chebyshev" || method == "gd" || method == "jacobi_gd" ||
                                 method == "nesterov" || method == "ncg" || method == "lbfgs" ||
                                 method == "newton";
  if (!evaluates_barrier)
    throw InputError(
        detail::concat(doc.where("solver.method"), ": ", what,
                       " with contact.method = \"energy\" (a barrier in "
                       "eps) need solver.method = chebyshev, gd, jacobi_gd, nesterov, ncg, lbfgs "
                       "or newton (got ",
                       method, "); contact.method = \"projection\" works with every method"));
  if (method == "newton" && scene.solver.newton_solver != "cg")
    throw InputError(
        detail::concat(doc.where("solver.newton_solver"), ": solver.newton_solver = \"",
                       scene.solver.newton_solver, "\" assembles no contact terms, and ", what,
                       " with contact.method = \"energy\" put a barrier in eps; use \"cg\""));
  // The multilevel operator takes the obstacles' blocks in at each refresh:
  // with chebyshev, which scales P^-1 where the barrier stiffens between
  // refreshes, and with newton, which refreshes it at each iteration's
  // Hessian; the other methods keep one P^-1 through a step while the
  // barrier stiffens. Between bodies only newton's takes the pairs (their
  // diagonal; CG's products hold the couplings). "auto" resolves to what
  // fits (preconditioners/make_preconditioner.hpp).
  const std::string& preconditioner = scene.solver.preconditioner;
  const bool other = preconditioner == "multilevel" || preconditioner == "petsc_gamg";
  const bool newton_multilevel = method == "newton" && preconditioner == "multilevel";
  if (other && !newton_multilevel && (between_bodies || method != "chebyshev"))
    throw InputError(
        detail::concat(doc.where("solver.preconditioner"), ": solver.preconditioner = \"",
                       preconditioner, "\" knows nothing of the contact barrier of ", what,
                       between_bodies ? "" : " with solver.method = " + method,
                       "; use \"auto\" or \"jacobi\", or contact.method = \"projection\""));
}

// A material parameter only some models use. Set to nonzero for another
// model it would be silently ignored, which almost always means the model was
// forgotten, so it is an error; 0 (its default) is accepted with any model.
void check_model_parameter(const SceneDocument& doc, std::string_view key, double value,
                           const std::string& model,
                           std::initializer_list<std::string_view> users) {
  if (value == 0 || std::find(users.begin(), users.end(), model) != users.end()) return;
  std::string listed;
  for (std::string_view user : users) {
    listed += (listed.empty() ? "\"" : "\" and \"") + std::string(user);
  }
  throw InputError(detail::concat(doc.where(key), ": ", key, " is used only by ", listed,
                                  "\", but material.model is \"", model, "\" (set ", key,
                                  " to 0 or change the model)"));
}

// The conversion parameters are checked even while it is disabled, so that
// switching it on (--set material.conversion.enabled=true) cannot fail late.
void check_conversion(const SceneDocument& doc, const ConversionSpec& conversion) {
  require(doc, conversion.lambda_minus >= 0, "material.conversion.lambda_minus", ">= 0",
          conversion.lambda_minus);
  if (conversion.lambda_minus >= conversion.lambda_plus) {
    // Either may be the one mistyped; point at one the scene sets.
    const char* culprit = doc.has("material.conversion.lambda_minus")
                              ? "material.conversion.lambda_minus"
                              : "material.conversion.lambda_plus";
    throw InputError(detail::concat(doc.where(culprit), ": material.conversion.lambda_minus (",
                                    format_number(conversion.lambda_minus),
                                    ") must be less than material.conversion.lambda_plus (",
                                    format_number(conversion.lambda_plus), ")"));
  }
  require(doc, conversion.decay >= 0, "material.conversion.decay", ">= 0", conversion.decay);
}

void check_material(const SceneDocument& doc, const MaterialSpec& material) {
  require_one_of(doc, "material.model", material.model,
                 {"stvk", "neo_hookean", "mooney_rivlin", "fung", "corotated", "arap"});
  require(doc, material.young > 0, "material.young", "> 0", material.young);
  require(doc, material.poisson > -1 && material.poisson < 0.5, "material.poisson", "in (-1, 0.5)",
          material.poisson);
  require(doc, material.density > 0, "material.density", "> 0", material.density);
  require(doc, material.c2 >= 0, "material.c2", ">= 0", material.c2);
  require(doc, material.c3 >= 0, "material.c3", ">= 0", material.c3);
  check_model_parameter(doc, "material.c2", material.c2, material.model, {"mooney_rivlin", "fung"});
  check_model_parameter(doc, "material.c3", material.c3, material.model, {"fung"});
  check_conversion(doc, material.conversion);
}

// solver.preconditioner and the multilevel hierarchy's keys. Only the
// methods that precondition their gradient take another P^-1 than Jacobi's.
void check_preconditioner(const SceneDocument& doc, const Scene& scene) {
  const SolverSpec& solver = scene.solver;
  require_one_of(doc, "solver.preconditioner", solver.preconditioner,
                 {"auto", "jacobi", "multilevel", "petsc_gamg"});
  require(doc, solver.preconditioner_refresh >= 1, "solver.preconditioner_refresh", ">= 1",
          solver.preconditioner_refresh);
  require(doc, solver.multilevel_cell >= 1.5 && solver.multilevel_cell <= 100,
          "solver.multilevel_cell", "in [1.5, 100] mean edge lengths", solver.multilevel_cell);
  require(doc, solver.multilevel_smoother_degree >= 1 && solver.multilevel_smoother_degree <= 16,
          "solver.multilevel_smoother_degree", "in [1, 16]", solver.multilevel_smoother_degree);
  require(doc, solver.multilevel_coarse_size >= 6 && solver.multilevel_coarse_size <= 100000,
          "solver.multilevel_coarse_size", "in [6, 100000] unknowns",
          solver.multilevel_coarse_size);
  // "auto" is the right one for every method.
  if (solver.preconditioner == "jacobi" || solver.preconditioner == "auto") return;
  const std::string& method = solver.method;
  const bool preconditions = method == "chebyshev" || method == "jacobi_gd" ||
                             method == "nesterov" || method == "ncg" || method == "lbfgs" ||
                             method == "linear_cg" || method == "newton";
  if (!preconditions)
    throw InputError(detail::concat(doc.where("solver.preconditioner"),
                                    ": solver.preconditioner = \"", solver.preconditioner,
                                    "\" preconditions chebyshev, jacobi_gd, nesterov, ncg, lbfgs, "
                                    "linear_cg and newton's CG, not ",
                                    method));
  // Newton's direct and PETSc solvers bring their own (none; PETSc's PC).
  if (method == "newton" && solver.newton_solver != "cg")
    throw InputError(detail::concat(doc.where("solver.preconditioner"),
                                    ": solver.preconditioner = \"", solver.preconditioner,
                                    "\" preconditions newton's CG (solver.newton_solver = \"cg\"), "
                                    "not solver.newton_solver = \"",
                                    solver.newton_solver, "\""));
  if (method == "chebyshev" && solver.chebyshev_parameters == "fixed")
    throw InputError(detail::concat(
        doc.where("solver.preconditioner"), ": solver.preconditioner = \"", solver.preconditioner,
        "\" takes Chebyshev's parameters from the spectrum of P^-1 H "
        "(solver.chebyshev_parameters = \"auto\"); the fixed ones are tuned to Jacobi's"));
  if (solver.preconditioner == "petsc_gamg" && scene.material.conversion.enabled)
    throw InputError(detail::concat(
        doc.where("solver.preconditioner"),
        ": solver.preconditioner = \"petsc_gamg\" needs material.conversion.enabled = false (its "
        "Hessian knows nothing of conversion's hybrid energy)"));
  if (method == "linear_cg" && doc.has("solver.linear_cg_preconditioner"))
    throw InputError(detail::concat(
        doc.where("solver.linear_cg_preconditioner"),
        ": solver.linear_cg_preconditioner and solver.preconditioner = \"", solver.preconditioner,
        "\" exclude each other (linear_cg then applies the latter)"));
}

// Paper 2's method is linearly implicit Euler on corotated elements: it needs
// a time step (no quasi-static solve) and the corotated model as it stands.
void check_linear_cg(const SceneDocument& doc, const Scene& scene) {
  const SolverSpec& solver = scene.solver;
  require_one_of(doc, "solver.linear_cg_guess", solver.linear_cg_guess,
                 {"zero", "velocity", "euler"});
  require_one_of(doc, "solver.linear_cg_preconditioner", solver.linear_cg_preconditioner,
                 {"identity", "mass", "jacobi"});
  require(doc, solver.linear_cg_tolerance >= 0, "solver.linear_cg_tolerance", ">= 0",
          solver.linear_cg_tolerance);
  require(doc, solver.polar_sweeps >= 1, "solver.polar_sweeps", ">= 1", solver.polar_sweeps);
  require(doc, solver.rayleigh_stiffness >= 0, "solver.rayleigh_stiffness", ">= 0",
          solver.rayleigh_stiffness);
  if (solver.method != "linear_cg") {
    if (solver.rayleigh_stiffness != 0)
      throw InputError(detail::concat(doc.where("solver.rayleigh_stiffness"),
                                      ": solver.rayleigh_stiffness applies to solver.method = "
                                      "linear_cg only (the descent methods minimise eps, which "
                                      "has no stiffness damping)"));
    return;
  }
  if (scene.material.model != "corotated" || scene.material.conversion.enabled)
    throw InputError(detail::concat(doc.where("solver.method"),
                                    ": solver.method = linear_cg needs material.model = "
                                    "\"corotated\" and material.conversion.enabled = false"));
  if (scene.time.quasistatic)
    throw InputError(detail::concat(doc.where("solver.method"),
                                    ": solver.method = linear_cg integrates in time and needs "
                                    "time.quasistatic = false"));
}

}  // namespace

void check_mesh_source(const SceneDocument& doc, const Scene& scene) {
  if (scene.bodies.empty()) {
    check_mesh_keys(doc, scene.mesh, scene_mesh_keys());
    return;
  }
  if (doc.has("mesh"))
    throw InputError(detail::concat(doc.where("mesh"),
                                    ": [mesh] and [[body]] exclude each other: each body names "
                                    "its own mesh (",
                                    doc.where("body.0"), " starts body.0)"));
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    check_mesh_keys(doc, scene.bodies[i].mesh, body_mesh_keys(detail::concat("body.", i)));
}

void apply_helix_preset(const SceneDocument& doc, SceneFields& fields) {
  apply_preset(doc, scene_mesh_keys(), fields.helix_preset, fields.scene.mesh.helix);
  std::vector<Body>& bodies = fields.scene.bodies;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    apply_preset(doc, body_mesh_keys(detail::concat("body.", i)), bodies[i].helix_preset,
                 bodies[i].mesh.helix);
}

void resolve_chebyshev_parameters(const SceneDocument& doc, SolverSpec& solver) {
  const char* fixed_key = nullptr;
  for (const char* key : {"solver.rho", "solver.phase_rho", "solver.alpha_max"})
    if (!fixed_key && doc.has(key)) fixed_key = key;
  if (!doc.has("solver.chebyshev_parameters")) {
    if (fixed_key) solver.chebyshev_parameters = "fixed";
  } else if (solver.chebyshev_parameters == "auto" && fixed_key) {
    // Both from one source: an override's key has replaced the file's
    // (scene_exclusions.hpp).
    throw InputError(detail::concat(
        doc.where(fixed_key), ": ", fixed_key,
        " is a fixed Chebyshev parameter, but solver.chebyshev_parameters = \"auto\" (",
        doc.where("solver.chebyshev_parameters"),
        ") takes alpha and rho from the spectrum: drop one of them"));
  }
  if (solver.chebyshev_parameters == "auto" && doc.has("solver.chebyshev_delay"))
    throw InputError(detail::concat(
        doc.where("solver.chebyshev_delay"),
        ": solver.chebyshev_delay applies to fixed Chebyshev parameters (set solver.rho and "
        "solver.alpha_max, or solver.chebyshev_parameters = \"fixed\"); the automatic "
        "parameters run plain iterations through the first check, then the recurrence"));
}

void resolve_step_accuracy(const SceneDocument& doc, SolverSpec& solver) {
  const bool gives_iterations = doc.has("solver.iterations");
  const bool counts_by_accuracy = solver.method == "chebyshev" && solver.phase_rho.size() <= 1;
  if (!doc.has("solver.accuracy") && !gives_iterations && counts_by_accuracy)
    solver.accuracy = kDefaultAccuracy;
  if (solver.accuracy > 0 && !gives_iterations) solver.iterations = kDefaultAccuracyCap;
}

void check_scene_values(const SceneDocument& doc, const Scene& scene) {
  require(doc, scene.mesh.scale > 0, "mesh.scale", "> 0", scene.mesh.scale);
  check_generator_values(doc, scene.mesh, scene_mesh_keys());

  check_material(doc, scene.material);

  visit_scene_arrays(scene, [&doc](std::string_view name, const auto& entries) {
    for (std::size_t i = 0; i < entries.size(); ++i) {
      check_entry(doc, entries[i], detail::concat(name, ".", i, "."));
    }
  });

  require(doc, scene.time.dt > 0, "time.dt", "> 0", scene.time.dt);
  require(doc, scene.time.frames >= 0, "time.frames", ">= 0", scene.time.frames);

  const SolverSpec& solver = scene.solver;
  require_one_of(doc, "solver.method", solver.method,
                 {"chebyshev", "gd", "jacobi_gd", "nesterov", "ncg", "lbfgs", "newton",
                  "pd_chebyshev", "linear_cg", "tao_bncg", "tao_blmvm"});
  // Projective dynamics is defined for the arap energy only (its constant
  // global matrix comes from |F - R|^2).
  if (solver.method == "pd_chebyshev" &&
      (scene.material.model != "arap" || scene.material.conversion.enabled))
    throw InputError(detail::concat(doc.where("solver.method"),
                                    ": solver.method = pd_chebyshev needs material.model = "
                                    "\"arap\" and material.conversion.enabled = false"));
  // Methods that use the elastic Hessian know nothing of conversion's hybrid
  // energy (its interpolants move with every gradient evaluation).
  if ((solver.method == "ncg" || solver.method == "newton") && scene.material.conversion.enabled)
    throw InputError(detail::concat(doc.where("solver.method"), ": solver.method = ", solver.method,
                                    " needs material.conversion.enabled = false"));
  for (double rho : solver.phase_rho)
    require(doc, rho >= 0 && rho < 1, "solver.phase_rho", "in [0, 1) for every phase", rho);
  for (int length : solver.phase_lengths)
    require(doc, length >= 1, "solver.phase_lengths", ">= 1 for every phase", length);
  if (!solver.phase_rho.empty() && solver.phase_lengths.size() + 1 != solver.phase_rho.size())
    throw InputError(detail::concat(doc.where("solver.phase_lengths"),
                                    ": solver.phase_lengths needs one length fewer than "
                                    "solver.phase_rho has phases (the last runs to the end)"));
  require(doc, solver.history >= 1, "solver.history", ">= 1", solver.history);
  require(doc, solver.newton_tolerance > 0, "solver.newton_tolerance", "> 0",
          solver.newton_tolerance);
  require(doc, solver.newton_iterations >= 1, "solver.newton_iterations", ">= 1",
          solver.newton_iterations);
  require_one_of(doc, "solver.newton_projection", solver.newton_projection, {"fallback", "always"});
  require(doc, solver.cg_tolerance > 0, "solver.cg_tolerance", "> 0", solver.cg_tolerance);
  require(doc, solver.cg_iterations >= 1, "solver.cg_iterations", ">= 1", solver.cg_iterations);
  require_one_of(doc, "solver.newton_solver", solver.newton_solver, {"cg", "ldlt", "petsc"});
  check_linear_cg(doc, scene);
  require(doc, solver.iterations >= 1, "solver.iterations", ">= 1", solver.iterations);
  check_preconditioner(doc, scene);
  require_one_of(doc, "solver.chebyshev_parameters", solver.chebyshev_parameters,
                 {"auto", "fixed"});
  require(doc, solver.accuracy >= 0 && solver.accuracy < 1, "solver.accuracy",
          "in [0, 1) (0: a fixed iteration count)", solver.accuracy);
  if (solver.accuracy > 0 && solver.method == "chebyshev" && solver.phase_rho.size() > 1)
    throw InputError(detail::concat(doc.where("solver.accuracy"),
                                    ": solver.accuracy counts iterations by one Chebyshev bound "
                                    "and does not combine with several solver.phase_rho"));
  require(doc, solver.spectrum_steps >= 2 && solver.spectrum_steps <= 1000, "solver.spectrum_steps",
          "in [2, 1000]", solver.spectrum_steps);
  require(doc, solver.spectrum_interval >= 0, "solver.spectrum_interval",
          ">= 0 (0: estimate again only after a rollback)", solver.spectrum_interval);
  require(doc, solver.spectrum_margin >= 0 && solver.spectrum_margin <= 10,
          "solver.spectrum_margin", "in [0, 10]", solver.spectrum_margin);
  require(doc, solver.rho >= 0 && solver.rho < 1, "solver.rho", "in [0, 1)", solver.rho);
  require(doc, solver.chebyshev_delay >= 0, "solver.chebyshev_delay", ">= 0",
          solver.chebyshev_delay);
  require(doc, solver.hessian_interval >= 1, "solver.hessian_interval", ">= 1",
          solver.hessian_interval);
  require(doc, solver.check_interval >= 1, "solver.check_interval", ">= 1", solver.check_interval);
  require(doc, solver.gamma > 0 && solver.gamma < 1, "solver.gamma", "in (0, 1)", solver.gamma);
  require(doc, solver.alpha_min > 0, "solver.alpha_min", "> 0", solver.alpha_min);
  if (solver.alpha_min > solver.alpha_max) {
    // Either may be the one mistyped; point at one the scene sets.
    const char* culprit = doc.has("solver.alpha_min") ? "solver.alpha_min" : "solver.alpha_max";
    throw InputError(detail::concat(
        doc.where(culprit), ": solver.alpha_min (", format_number(solver.alpha_min),
        ") must not exceed solver.alpha_max (", format_number(solver.alpha_max), ")"));
  }
  require_one_of(doc, "solver.init", solver.init,
                 {"constant_acceleration", "position", "velocity", "optimized"});
  require(doc, solver.eta >= 0, "solver.eta", ">= 0", solver.eta);
  require(doc, solver.damping >= 0, "solver.damping", ">= 0", solver.damping);

  check_contact(doc, scene);

  require_one_of(doc, "partition.method", scene.partition.method,
                 {"auto", "metis", "ptscotch", "rcb"});
  require(doc, scene.partition.tries >= 1 && scene.partition.tries <= 100, "partition.tries",
          "in [1, 100]", scene.partition.tries);
  require_one_of(doc, "partition.reorder", scene.partition.reorder, {"rcm", "none"});

  if (scene.output.dir.empty()) {
    throw InputError(detail::concat(doc.where("output.dir"), ": output.dir must not be empty"));
  }
  require(doc, scene.output.every >= 1, "output.every", ">= 1", scene.output.every);
  require(doc, scene.output.checkpoint_every >= 0, "output.checkpoint_every", ">= 0",
          scene.output.checkpoint_every);
}

}  // namespace descent
