// Keys that exclude each other (io/scene_exclusions.hpp), pair by pair: an
// override's key replaces the file's key that it excludes, and either source
// setting both keys alone is an error naming both.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "io/scene.hpp"
#include "io/scene_document.hpp"
#include "io/scene_exclusions.hpp"
#include "io/scene_overrides.hpp"

namespace descent {
namespace {

// One pair, each key as a line of a scene file and as an override, and a
// file that sets both. `context` makes the pair apply ("auto" excludes the
// fixed keys, linear_cg's preconditioner excludes another than Jacobi's)
// and the rest of the scene valid, so the exclusion is the error.
struct PairCase {
  std::string first;  // the keys, as scene_exclusions names them
  std::string second;
  std::string context;
  std::string first_toml;
  std::string second_toml;
  std::string both_toml;
  std::string first_set;
  std::string second_set;
  // Overrides that make a scene of the two overrides valid but for them.
  std::vector<std::string> set_context = {};
};

const std::string kLinearCg =
    "solver.method = \"linear_cg\"\nmaterial.model = \"corotated\"\nmesh.generator = \"box\"\n";

std::vector<PairCase> pair_cases() {
  return {
      {"mesh", "body", "", "mesh.generator = \"box\"\n",
       "body = [{ generator = { kind = \"ball\" } }]\n",
       "mesh.generator = \"box\"\nbody = [{ generator = { kind = \"ball\" } }]\n",
       "mesh.generator=box", "body.0.generator.kind=ball"},
      {"mesh.file", "mesh.generator", "", "mesh.file = \"a.msh\"\n", "mesh.generator = \"box\"\n",
       "mesh.file = \"a.msh\"\nmesh.generator = \"box\"\n", "mesh.file=a.msh",
       "mesh.generator=box"},
      {"mesh.file", "mesh.helix", "", "mesh.file = \"a.msh\"\n", "mesh.helix.turns = 3\n",
       "mesh.file = \"a.msh\"\nmesh.helix.turns = 3\n", "mesh.file=a.msh", "mesh.helix.turns=3"},
      {"mesh.file", "mesh.box", "", "mesh.file = \"a.msh\"\n", "mesh.box.cells = [1, 1, 1]\n",
       "mesh.file = \"a.msh\"\nmesh.box.cells = [1, 1, 1]\n", "mesh.file=a.msh",
       "mesh.box.cells=[1,1,1]"},
      {"mesh.file", "mesh.ball", "", "mesh.file = \"a.msh\"\n", "mesh.ball.cells = 3\n",
       "mesh.file = \"a.msh\"\nmesh.ball.cells = 3\n", "mesh.file=a.msh", "mesh.ball.cells=3"},
      {"mesh.file", "mesh.car", "", "mesh.file = \"a.msh\"\n", "mesh.car.cells = 12\n",
       "mesh.file = \"a.msh\"\nmesh.car.cells = 12\n", "mesh.file=a.msh", "mesh.car.cells=12"},
      {"mesh.helix.resolution", "mesh.helix.preset", "mesh.generator = \"double_helix\"\n",
       "mesh.helix.resolution = 2\n", "mesh.helix.preset = \"41k\"\n",
       "mesh.helix.resolution = 2\nmesh.helix.preset = \"41k\"\n", "mesh.helix.resolution=7.15",
       "mesh.helix.preset=41k"},
      {"body.0.file", "body.0.generator", "", "body = [{ file = \"a.msh\" }]\n",
       "body = [{ generator = { kind = \"box\" } }]\n",
       "body = [{ file = \"a.msh\", generator = { kind = \"box\" } }]\n", "body.0.file=a.msh",
       "body.0.generator.kind=box"},
      {"body.0.generator.helix.resolution",
       "body.0.generator.helix.preset",
       "",
       "body = [{ generator = { kind = \"double_helix\", helix = { resolution = 2 } } }]\n",
       "body = [{ generator = { kind = \"double_helix\", helix = { preset = \"41k\" } } }]\n",
       "body = [{ generator = { kind = \"double_helix\", helix = { resolution = 2, preset = "
       "\"41k\" } } }]\n",
       "body.0.generator.helix.resolution=2",
       "body.0.generator.helix.preset=41k",
       {"body.0.generator.kind=double_helix"}},
      {"solver.chebyshev_parameters", "solver.rho", "mesh.generator = \"box\"\n",
       "solver.chebyshev_parameters = \"auto\"\n", "solver.rho = 0.9\n",
       "solver.chebyshev_parameters = \"auto\"\nsolver.rho = 0.9\n",
       "solver.chebyshev_parameters=auto", "solver.rho=0.9"},
      {"solver.chebyshev_parameters", "solver.phase_rho", "mesh.generator = \"box\"\n",
       "solver.chebyshev_parameters = \"auto\"\n", "solver.phase_rho = [0.9]\n",
       "solver.chebyshev_parameters = \"auto\"\nsolver.phase_rho = [0.9]\n",
       "solver.chebyshev_parameters=auto", "solver.phase_rho=[0.9]"},
      {"solver.chebyshev_parameters", "solver.alpha_max", "mesh.generator = \"box\"\n",
       "solver.chebyshev_parameters = \"auto\"\n", "solver.alpha_max = 0.5\n",
       "solver.chebyshev_parameters = \"auto\"\nsolver.alpha_max = 0.5\n",
       "solver.chebyshev_parameters=auto", "solver.alpha_max=0.5"},
      {"solver.chebyshev_parameters", "solver.chebyshev_delay", "mesh.generator = \"box\"\n",
       "solver.chebyshev_parameters = \"auto\"\n", "solver.chebyshev_delay = 4\n",
       "solver.chebyshev_parameters = \"auto\"\nsolver.chebyshev_delay = 4\n",
       "solver.chebyshev_parameters=auto", "solver.chebyshev_delay=4"},
      {"solver.linear_cg_preconditioner", "solver.preconditioner", kLinearCg,
       "solver.linear_cg_preconditioner = \"mass\"\n", "solver.preconditioner = \"multilevel\"\n",
       "solver.linear_cg_preconditioner = \"mass\"\nsolver.preconditioner = \"multilevel\"\n",
       "solver.linear_cg_preconditioner=mass", "solver.preconditioner=multilevel"},
  };
}

SceneDocument document(const std::string& text, const std::vector<std::string>& overrides) {
  SceneDocument doc{toml::parse(text, std::string("scene.toml")), "scene.toml"};
  apply_overrides(doc.root, overrides);
  replace_excluded_keys(doc);
  return doc;
}

std::string error_of(const std::string& text, const std::vector<std::string>& overrides) {
  try {
    parse_scene(text, "scene.toml", overrides);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return "";
}

// The table of pairs and the cases here list the same pairs: a pair added
// to the table without a case fails here.
TEST(SceneExclusions, EveryPairHasACase) {
  const SceneDocument one_body = document("body = [{ file = \"a.msh\" }]\n", {});
  std::set<std::pair<std::string, std::string>> table, cases;
  for (const Exclusion& pair : scene_exclusions(one_body)) table.insert({pair.first, pair.second});
  for (const PairCase& c : pair_cases()) cases.insert({c.first, c.second});
  EXPECT_EQ(table, cases);
}

TEST(SceneExclusions, TheOverridesKeyReplacesTheFilesKey) {
  for (const PairCase& c : pair_cases()) {
    SCOPED_TRACE(c.first + " / " + c.second);
    const SceneDocument second_wins = document(c.context + c.first_toml, {c.second_set});
    EXPECT_FALSE(second_wins.has(c.first));
    EXPECT_TRUE(second_wins.has(c.second));
    const SceneDocument first_wins = document(c.context + c.second_toml, {c.first_set});
    EXPECT_TRUE(first_wins.has(c.first));
    EXPECT_FALSE(first_wins.has(c.second));
  }
}

TEST(SceneExclusions, OneSourceSettingBothIsAnErrorNamingBoth) {
  for (const PairCase& c : pair_cases()) {
    SCOPED_TRACE(c.first + " / " + c.second);
    // The file: both keys stay for the checks, which name them and the line.
    const SceneDocument file = document(c.context + c.both_toml, {});
    EXPECT_TRUE(file.has(c.first) && file.has(c.second));
    const std::string in_file = error_of(c.context + c.both_toml, {});
    EXPECT_NE(in_file.find("scene.toml:"), std::string::npos) << in_file;
    // The command line is one source too.
    std::vector<std::string> overrides = c.set_context;
    overrides.insert(overrides.end(), {c.first_set, c.second_set});
    const std::string in_overrides = error_of(c.context, overrides);
    EXPECT_NE(in_overrides.find("--set "), std::string::npos) << in_overrides;
    for (const std::string& message : {in_file, in_overrides}) {
      EXPECT_NE(message.find(c.first), std::string::npos) << message;
      EXPECT_NE(message.find(c.second), std::string::npos) << message;
    }
  }
}

// The pairs that depend on a value leave other values alone.
TEST(SceneExclusions, FixedChebyshevKeepsItsKeys) {
  const SceneDocument fixed =
      document("solver.chebyshev_parameters = \"fixed\"\n", {"solver.rho=0.9"});
  EXPECT_TRUE(fixed.has("solver.chebyshev_parameters"));
  EXPECT_TRUE(fixed.has("solver.rho"));
  const SceneDocument jacobi = document(kLinearCg + "solver.linear_cg_preconditioner = \"mass\"\n",
                                        {"solver.preconditioner=jacobi"});
  EXPECT_TRUE(jacobi.has("solver.linear_cg_preconditioner"));
}

// The resolution study: a preset scene takes another resolution
// from the command line, and the resolution is the one given.
TEST(SceneExclusions, AResolutionOverridesThePreset) {
  const Scene scene =
      parse_scene("[mesh]\ngenerator = \"double_helix\"\n[mesh.helix]\npreset = \"82k\"\n",
                  "scene.toml", {"mesh.helix.resolution=7.15"});
  EXPECT_EQ(scene.mesh.helix.resolution, 7.15);
  // A file mesh given on the command line drops the generator and its table.
  const Scene from_file =
      parse_scene("[mesh]\ngenerator = \"double_helix\"\n[mesh.helix]\npreset = \"82k\"\n",
                  "scene.toml", {"mesh.file=a.msh"});
  EXPECT_EQ(from_file.mesh.file, "a.msh");
  EXPECT_EQ(from_file.mesh.generator, "");
}

}  // namespace
}  // namespace descent
