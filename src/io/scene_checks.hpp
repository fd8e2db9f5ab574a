#pragma once
// Checks of scene values past their types: the mesh source, allowed names
// and numeric ranges. Each throws InputError naming the key and where it
// was set.
#include "io/scene_document.hpp"
#include "io/scene_schema.hpp"

namespace descent {

// Exactly one of mesh.generator / mesh.file, a known generator, and the
// parameter table ([mesh.helix], [mesh.box]) of that generator only; the
// same for each [[body]] (file / generator.kind), which excludes [mesh].
void check_mesh_source(const SceneDocument& doc, const Scene& scene);

// mesh.helix.preset (which conflicts with mesh.helix.resolution) sets the
// helix resolution; each body's generator.helix.preset likewise.
void apply_helix_preset(const SceneDocument& doc, SceneFields& fields);

// solver.chebyshev_parameters from the keys the scene sets: "fixed" when it
// sets rho, phase_rho or alpha_max and does not say. A fixed key beside an
// explicit "auto" is an error naming both keys (an override's key has
// already replaced the file's: scene_exclusions.hpp); so is chebyshev_delay
// with the automatic parameters.
void resolve_chebyshev_parameters(const SceneDocument& doc, SolverSpec& solver);

// How many iterations a step runs: without solver.accuracy and
// solver.iterations, Chebyshev with at most one phase (the method that
// counts by an accuracy) runs to kDefaultAccuracy, and other methods keep
// the fixed count; wherever an accuracy is in effect and the scene gives no
// `iterations`, the cap is kDefaultAccuracyCap. A scene that gives only
// `iterations` runs that many.
void resolve_step_accuracy(const SceneDocument& doc, SolverSpec& solver);

// Names of models and methods, numeric ranges, model parameters (c2, c3)
// only with the models that use them, [[fixed]] regions with their motions
// and [[load]] regions.
void check_scene_values(const SceneDocument& doc, const Scene& scene);

}  // namespace descent
