#include "io/scene_exclusions.hpp"

#include "common/error.hpp"

namespace descent {

namespace {

bool string_is(const SceneDocument& doc, std::string_view key, std::string_view value) {
  const toml::node* node = doc.find(key);
  return node && node->is_string() && node->as_string()->get() == value;
}

// "auto" takes alpha and rho from the spectrum; "fixed" runs the given ones.
bool automatic_chebyshev(const SceneDocument& doc) {
  return string_is(doc, "solver.chebyshev_parameters", "auto");
}

// linear_cg applies solver.preconditioner when it is one other than Jacobi's.
bool linear_cg_preconditioned(const SceneDocument& doc) {
  return string_is(doc, "solver.method", "linear_cg") &&
         !string_is(doc, "solver.preconditioner", "auto") &&
         !string_is(doc, "solver.preconditioner", "jacobi");
}

// The keys of one mesh source: [mesh] with its generator's tables, or a
// [[body]], whose [body.generator] holds the kind and the tables.
void add_mesh_exclusions(const std::string& file, const std::vector<std::string>& generator_keys,
                         const std::string& helix, std::vector<Exclusion>& pairs) {
  for (const std::string& key : generator_keys) pairs.push_back({file, key});
  pairs.push_back({helix + ".resolution", helix + ".preset"});  // a preset names a resolution
}

}  // namespace

std::vector<Exclusion> scene_exclusions(const SceneDocument& doc) {
  std::vector<Exclusion> pairs;
  pairs.push_back({"mesh", "body"});  // each body names its own mesh
  add_mesh_exclusions("mesh.file",
                      {"mesh.generator", "mesh.helix", "mesh.box", "mesh.ball", "mesh.car"},
                      "mesh.helix", pairs);
  if (const toml::node* bodies = doc.find("body"); bodies && bodies->is_array()) {
    for (std::size_t i = 0; i < bodies->as_array()->size(); ++i) {
      const std::string body = detail::concat("body.", i);
      add_mesh_exclusions(body + ".file", {body + ".generator"}, body + ".generator.helix", pairs);
    }
  }
  for (const char* fixed :
       {"solver.rho", "solver.phase_rho", "solver.alpha_max", "solver.chebyshev_delay"})
    pairs.push_back({"solver.chebyshev_parameters", fixed, automatic_chebyshev});
  pairs.push_back(
      {"solver.linear_cg_preconditioner", "solver.preconditioner", linear_cg_preconditioned});
  return pairs;
}

void replace_excluded_keys(SceneDocument& doc) {
  for (const Exclusion& pair : scene_exclusions(doc)) {
    const toml::node* first = doc.find(pair.first);
    const toml::node* second = doc.find(pair.second);
    if (!first || !second || (pair.applies && !pair.applies(doc))) continue;
    const bool first_overridden = doc.set_by_override(*first);
    const bool second_overridden = doc.set_by_override(*second);
    if (first_overridden && !second_overridden) doc.erase(pair.second);
    if (second_overridden && !first_overridden) doc.erase(pair.first);
  }
}

}  // namespace descent
