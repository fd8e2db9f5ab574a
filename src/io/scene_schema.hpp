#pragma once
// The one list of scene keys. Every stage of scene reading walks it: the
// unknown-key check (and its suggestions) and the typed reading, so a key
// added here is accepted, suggested and read, with its type taken from the
// field it fills. A dotted key ("motion.kind") lives in a nested table,
// which the unknown-key check then accepts as a table.
#include <string>
#include <string_view>

#include "io/scene.hpp"

namespace descent {

// What a scene file can set: the Scene itself plus keys that only steer
// parsing and have no field of their own.
struct SceneFields {
  Scene scene;
  std::string helix_preset;  // mesh.helix.preset: a named mesh.helix.resolution
};

// The parameter tables of the generators ([mesh.helix], [mesh.box],
// [mesh.ball], [mesh.car]) below `prefix` ("mesh.", a body's "generator."), but
// helix.preset, which fills no MeshSpec field.
template <class Visit>
void visit_generator_keys(MeshSpec& mesh, const std::string& prefix, Visit&& visit) {
  visit(prefix + "helix.resolution", mesh.helix.resolution);
  visit(prefix + "helix.helix_radius", mesh.helix.helix_radius);
  visit(prefix + "helix.tube_radius", mesh.helix.tube_radius);
  visit(prefix + "helix.pitch", mesh.helix.pitch);
  visit(prefix + "helix.turns", mesh.helix.turns);
  visit(prefix + "box.cells", mesh.box.cells);
  visit(prefix + "box.size", mesh.box.size);
  visit(prefix + "box.origin", mesh.box.origin);
  visit(prefix + "box.tets_per_cell", mesh.box.tets_per_cell);
  visit(prefix + "ball.cells", mesh.ball.cells);
  visit(prefix + "ball.radius", mesh.ball.radius);
  visit(prefix + "ball.centre", mesh.ball.centre);
  visit(prefix + "car.cells", mesh.car.cells);
  visit(prefix + "car.length", mesh.car.length);
  visit(prefix + "car.width", mesh.car.width);
  visit(prefix + "car.height", mesh.car.height);
  visit(prefix + "car.origin", mesh.car.origin);
}

// Calls visit(dotted_key, field) for every key outside the arrays of tables.
template <class Visit>
void visit_scene_keys(SceneFields& fields, Visit&& visit) {
  Scene& scene = fields.scene;
  MeshSpec& mesh = scene.mesh;
  visit("mesh.generator", mesh.generator);
  visit("mesh.file", mesh.file);
  visit("mesh.scale", mesh.scale);
  visit("mesh.helix.preset", fields.helix_preset);
  visit_generator_keys(mesh, "mesh.", visit);

  visit("material.model", scene.material.model);
  visit("material.young", scene.material.young);
  visit("material.poisson", scene.material.poisson);
  visit("material.density", scene.material.density);
  visit("material.c2", scene.material.c2);
  visit("material.c3", scene.material.c3);
  ConversionSpec& conversion = scene.material.conversion;
  visit("material.conversion.enabled", conversion.enabled);
  visit("material.conversion.lambda_minus", conversion.lambda_minus);
  visit("material.conversion.lambda_plus", conversion.lambda_plus);
  visit("material.conversion.decay", conversion.decay);
  visit("gravity", scene.gravity);

  visit("time.dt", scene.time.dt);
  visit("time.frames", scene.time.frames);
  visit("time.quasistatic", scene.time.quasistatic);

  SolverSpec& solver = scene.solver;
  visit("solver.method", solver.method);
  visit("solver.chebyshev_parameters", solver.chebyshev_parameters);
  visit("solver.iterations", solver.iterations);
  visit("solver.accuracy", solver.accuracy);
  visit("solver.spectrum_steps", solver.spectrum_steps);
  visit("solver.spectrum_interval", solver.spectrum_interval);
  visit("solver.spectrum_margin", solver.spectrum_margin);
  visit("solver.rho", solver.rho);
  visit("solver.chebyshev_delay", solver.chebyshev_delay);
  visit("solver.hessian_interval", solver.hessian_interval);
  visit("solver.check_interval", solver.check_interval);
  visit("solver.gamma", solver.gamma);
  visit("solver.alpha_max", solver.alpha_max);
  visit("solver.alpha_min", solver.alpha_min);
  visit("solver.init", solver.init);
  visit("solver.eta", solver.eta);
  visit("solver.damping", solver.damping);
  visit("solver.phase_rho", solver.phase_rho);
  visit("solver.phase_lengths", solver.phase_lengths);
  visit("solver.history", solver.history);
  visit("solver.newton_tolerance", solver.newton_tolerance);
  visit("solver.newton_iterations", solver.newton_iterations);
  visit("solver.newton_projection", solver.newton_projection);
  visit("solver.cg_tolerance", solver.cg_tolerance);
  visit("solver.cg_iterations", solver.cg_iterations);
  visit("solver.newton_solver", solver.newton_solver);
  visit("solver.petsc_options", solver.petsc_options);
  visit("solver.linear_cg_guess", solver.linear_cg_guess);
  visit("solver.linear_cg_preconditioner", solver.linear_cg_preconditioner);
  visit("solver.linear_cg_tolerance", solver.linear_cg_tolerance);
  visit("solver.polar_sweeps", solver.polar_sweeps);
  visit("solver.rayleigh_stiffness", solver.rayleigh_stiffness);
  visit("solver.preconditioner", solver.preconditioner);
  visit("solver.preconditioner_refresh", solver.preconditioner_refresh);
  visit("solver.multilevel_cell", solver.multilevel_cell);
  visit("solver.multilevel_smoother_degree", solver.multilevel_smoother_degree);
  visit("solver.multilevel_coarse_size", solver.multilevel_coarse_size);

  visit("contact.method", scene.contact.method);
  visit("contact.distance", scene.contact.distance);
  visit("contact.stiffness", scene.contact.stiffness);
  visit("contact.smoothing_velocity", scene.contact.smoothing_velocity);
  visit("contact.self", scene.contact.self);
  visit("contact.friction", scene.contact.friction);

  visit("partition.method", scene.partition.method);
  visit("partition.tries", scene.partition.tries);
  visit("partition.reorder", scene.partition.reorder);

  visit("output.dir", scene.output.dir);
  visit("output.every", scene.output.every);
  visit("output.checkpoint_every", scene.output.checkpoint_every);
}

// The scene's arrays of tables ([[fixed]], [[load]], [[obstacle]], [[body]]): calls
// visit(name, entries) for each, `entries` being the vector its tables fill.
// Each table holds the keys that visit_entry_keys lists for its entry type,
// addressed in messages and overrides as fixed.0.axes, load.1.force, ...
// A const Scene gives const vectors, for the checks of the entries.
template <class SceneType, class Visit>
void visit_scene_arrays(SceneType& scene, Visit&& visit) {
  visit("fixed", scene.fixed);
  visit("load", scene.loads);
  visit("obstacle", scene.obstacles);
  visit("body", scene.bodies);
}

// The keys of an optional motion table ([fixed.motion], [obstacle.motion]).
template <class Visit>
void visit_motion_keys(Motion& motion, Visit&& visit) {
  visit("motion.kind", motion.kind);
  visit("motion.velocity", motion.velocity);
  visit("motion.axis", motion.axis);
  visit("motion.centre", motion.centre);
  visit("motion.angular_velocity", motion.angular_velocity);
  visit("motion.until", motion.until);
}

template <class Visit>
void visit_entry_keys(FixedRegion& region, Visit&& visit) {
  visit("box_min", region.box_min);
  visit("box_max", region.box_max);
  visit("axes", region.axes);
  visit_motion_keys(region.motion, visit);
}

template <class Visit>
void visit_entry_keys(Obstacle& obstacle, Visit&& visit) {
  visit("kind", obstacle.kind);
  visit("point", obstacle.point);
  visit("normal", obstacle.normal);
  visit("centre", obstacle.centre);
  visit("radius", obstacle.radius);
  visit("box_min", obstacle.box_min);
  visit("box_max", obstacle.box_max);
  visit("friction", obstacle.friction);
  visit_motion_keys(obstacle.motion, visit);
}

// A [[body]]: the mesh keys of [mesh] (the generator's under `generator`),
// its placement, initial velocity and material overrides.
template <class Visit>
void visit_entry_keys(Body& body, Visit&& visit) {
  MeshSpec& mesh = body.mesh;
  visit("file", mesh.file);
  visit("generator.kind", mesh.generator);
  visit("generator.helix.preset", body.helix_preset);
  visit_generator_keys(mesh, "generator.", visit);
  visit("scale", body.scale);
  visit("rotate.axis", body.rotate_axis);
  visit("rotate.degrees", body.rotate_degrees);
  visit("translate", body.translate);
  visit("velocity", body.velocity);
  visit("angular_velocity", body.angular_velocity);
  visit("material.young", body.young);
  visit("material.density", body.density);
}

template <class Visit>
void visit_entry_keys(LoadRegion& region, Visit&& visit) {
  visit("box_min", region.box_min);
  visit("box_max", region.box_max);
  visit("force", region.force);
  visit("ramp", region.ramp);
}

}  // namespace descent
