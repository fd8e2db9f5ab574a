// Scene files: defaults, every key, every error a user can make (named by
// key and line), and --set overrides checked exactly like file entries.
#include <gtest/gtest.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "io/scene.hpp"
#include "meshes/generators.hpp"

namespace descent {
namespace {

namespace fs = std::filesystem;
using Overrides = std::vector<std::string>;
using Vec3 = std::array<double, 3>;

// The smallest valid scenes: two lines each.
constexpr const char* kBoxScene = "[mesh]\ngenerator = \"box\"\n";
constexpr const char* kHelixScene = "[mesh]\ngenerator = \"double_helix\"\n";

Scene parse(const std::string& text, const Overrides& overrides = {}) {
  return parse_scene(text, "scene.toml", overrides);
}

// The message of the InputError that parsing throws.
std::string error_of(const std::string& text, const Overrides& overrides = {}) {
  try {
    parse(text, overrides);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return "";
}

void expect_has(const std::string& message, const std::string& part) {
  EXPECT_NE(message.find(part), std::string::npos)
      << "message: " << message << "\nlacks:   " << part;
}

// A folder of its own under the system temp folder, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const std::string test = testing::UnitTest::GetInstance()->current_test_info()->name();
    path_ = fs::temp_directory_path() /
            ("descent_test_scene_" + test + "_" + std::to_string(::getpid()));
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path file = path_ / name;
    fs::create_directories(file.parent_path());
    std::ofstream(file) << text;
    return file;
  }

 private:
  fs::path path_;
};

// ---------------------------------------------------------------- defaults

TEST(Scene, EmptySceneNeedsAMesh) {
  const std::string message = error_of("");
  expect_has(message, "scene.toml");
  expect_has(message, "mesh.generator");
  expect_has(message, "mesh.file");
}

TEST(Scene, EveryOtherKeyDefaultsToTheStructDefaults) {
  const Scene scene = parse(kHelixScene);
  const Scene defaults;
  EXPECT_EQ(scene.source, "scene.toml");
  EXPECT_EQ(scene.mesh.generator, "double_helix");
  EXPECT_EQ(scene.mesh.file, "");
  EXPECT_EQ(scene.mesh.scale, defaults.mesh.scale);
  EXPECT_EQ(scene.mesh.helix.resolution, defaults.mesh.helix.resolution);
  EXPECT_EQ(scene.mesh.helix.helix_radius, defaults.mesh.helix.helix_radius);
  EXPECT_EQ(scene.mesh.helix.tube_radius, defaults.mesh.helix.tube_radius);
  EXPECT_EQ(scene.mesh.helix.pitch, defaults.mesh.helix.pitch);
  EXPECT_EQ(scene.mesh.helix.turns, defaults.mesh.helix.turns);
  EXPECT_EQ(scene.mesh.box.cells, defaults.mesh.box.cells);
  EXPECT_EQ(scene.mesh.box.size, defaults.mesh.box.size);
  EXPECT_EQ(scene.mesh.box.origin, defaults.mesh.box.origin);
  EXPECT_EQ(scene.mesh.box.tets_per_cell, defaults.mesh.box.tets_per_cell);
  EXPECT_EQ(scene.material.model, defaults.material.model);
  EXPECT_EQ(scene.material.young, defaults.material.young);
  EXPECT_EQ(scene.material.poisson, defaults.material.poisson);
  EXPECT_EQ(scene.material.density, defaults.material.density);
  EXPECT_EQ(scene.material.c2, defaults.material.c2);
  EXPECT_EQ(scene.material.c3, defaults.material.c3);
  EXPECT_EQ(scene.material.conversion.enabled, defaults.material.conversion.enabled);
  EXPECT_EQ(scene.material.conversion.lambda_minus, defaults.material.conversion.lambda_minus);
  EXPECT_EQ(scene.material.conversion.lambda_plus, defaults.material.conversion.lambda_plus);
  EXPECT_EQ(scene.material.conversion.decay, defaults.material.conversion.decay);
  EXPECT_EQ(scene.gravity, defaults.gravity);
  EXPECT_TRUE(scene.fixed.empty());
  EXPECT_TRUE(scene.loads.empty());
  EXPECT_EQ(scene.time.dt, defaults.time.dt);
  EXPECT_EQ(scene.time.frames, defaults.time.frames);
  EXPECT_EQ(scene.time.quasistatic, defaults.time.quasistatic);
  EXPECT_EQ(scene.solver.method, defaults.solver.method);
  EXPECT_EQ(scene.solver.chebyshev_parameters, "auto");
  // No solver keys: Chebyshev runs each step to the default accuracy.
  EXPECT_EQ(scene.solver.accuracy, kDefaultAccuracy);
  EXPECT_EQ(scene.solver.iterations, kDefaultAccuracyCap);
  EXPECT_EQ(scene.solver.spectrum_steps, defaults.solver.spectrum_steps);
  EXPECT_EQ(scene.solver.spectrum_interval, defaults.solver.spectrum_interval);
  EXPECT_EQ(scene.solver.spectrum_margin, defaults.solver.spectrum_margin);
  EXPECT_EQ(scene.solver.rho, defaults.solver.rho);
  EXPECT_EQ(scene.solver.chebyshev_delay, defaults.solver.chebyshev_delay);
  EXPECT_EQ(scene.solver.hessian_interval, defaults.solver.hessian_interval);
  EXPECT_EQ(scene.solver.check_interval, defaults.solver.check_interval);
  EXPECT_EQ(scene.solver.gamma, defaults.solver.gamma);
  EXPECT_EQ(scene.solver.alpha_max, defaults.solver.alpha_max);
  EXPECT_EQ(scene.solver.alpha_min, defaults.solver.alpha_min);
  EXPECT_EQ(scene.solver.init, defaults.solver.init);
  EXPECT_EQ(scene.solver.eta, defaults.solver.eta);
  EXPECT_EQ(scene.solver.damping, defaults.solver.damping);
  EXPECT_EQ(scene.output.dir, defaults.output.dir);
  EXPECT_EQ(scene.output.every, defaults.output.every);
}

// --------------------------------------------------------------- every key

TEST(Scene, ReadsEveryKeyOfAHelixScene) {
  const Scene scene = parse(R"(
gravity = [0, 0, -9.81]

[mesh]
generator = "double_helix"
scale = 2.5
[mesh.helix]
resolution = 1.5
helix_radius = 0.3
tube_radius = 0.1
pitch = 0.6
turns = 3

[material]
model = "neo_hookean"
young = 2e6
poisson = 0.45
density = 1100

[[fixed]]
box_min = [-1, -1, -1]
box_max = [1, 0.05, 1]

[[fixed]]
box_min = [0, 1, 0]
box_max = [2, 2, 2]
axes = "xz"

[time]
dt = 0.01
frames = 120

[solver]
method = "chebyshev"
iterations = 64
rho = 0.9
chebyshev_delay = 5
hessian_interval = 16
check_interval = 4
gamma = 0.5
alpha_max = 0.8
alpha_min = 0.01
init = "velocity"
eta = 0.3
damping = 0.1

[output]
dir = "runs/helix"
every = 2
)");
  EXPECT_EQ(scene.mesh.generator, "double_helix");
  EXPECT_EQ(scene.mesh.scale, 2.5);
  EXPECT_EQ(scene.mesh.helix.resolution, 1.5);
  EXPECT_EQ(scene.mesh.helix.helix_radius, 0.3);
  EXPECT_EQ(scene.mesh.helix.tube_radius, 0.1);
  EXPECT_EQ(scene.mesh.helix.pitch, 0.6);
  EXPECT_EQ(scene.mesh.helix.turns, 3.0);
  EXPECT_EQ(scene.material.model, "neo_hookean");
  EXPECT_EQ(scene.material.young, 2e6);
  EXPECT_EQ(scene.material.poisson, 0.45);
  EXPECT_EQ(scene.material.density, 1100.0);
  EXPECT_EQ(scene.gravity, (Vec3{0, 0, -9.81}));
  ASSERT_EQ(scene.fixed.size(), 2u);
  EXPECT_EQ(scene.fixed[0].box_min, (Vec3{-1, -1, -1}));
  EXPECT_EQ(scene.fixed[0].box_max, (Vec3{1, 0.05, 1}));
  EXPECT_EQ(scene.fixed[0].axes, "xyz");
  EXPECT_EQ(scene.fixed[1].box_min, (Vec3{0, 1, 0}));
  EXPECT_EQ(scene.fixed[1].box_max, (Vec3{2, 2, 2}));
  EXPECT_EQ(scene.fixed[1].axes, "xz");
  EXPECT_EQ(scene.time.dt, 0.01);
  EXPECT_EQ(scene.time.frames, 120);
  EXPECT_EQ(scene.solver.method, "chebyshev");
  EXPECT_EQ(scene.solver.iterations, 64);
  EXPECT_EQ(scene.solver.rho, 0.9);
  EXPECT_EQ(scene.solver.chebyshev_delay, 5);
  EXPECT_EQ(scene.solver.hessian_interval, 16);
  EXPECT_EQ(scene.solver.check_interval, 4);
  EXPECT_EQ(scene.solver.gamma, 0.5);
  EXPECT_EQ(scene.solver.alpha_max, 0.8);
  EXPECT_EQ(scene.solver.alpha_min, 0.01);
  EXPECT_EQ(scene.solver.init, "velocity");
  EXPECT_EQ(scene.solver.eta, 0.3);
  EXPECT_EQ(scene.solver.damping, 0.1);
  EXPECT_EQ(scene.output.dir, "runs/helix");
  EXPECT_EQ(scene.output.every, 2);
}

TEST(Scene, EveryModelNameIsAccepted) {
  for (const char* model : {"stvk", "neo_hookean", "mooney_rivlin", "fung", "corotated", "arap"}) {
    SCOPED_TRACE(model);
    const std::string text = std::string(kBoxScene) + "[material]\nmodel = \"" + model + "\"\n";
    EXPECT_EQ(parse(text).material.model, model);
  }
}

TEST(Scene, ReadsEveryMaterialKeyOfFung) {
  const Scene scene = parse(std::string(kBoxScene) + R"(
[material]
model = "fung"
c2 = 2000
c3 = 1.5
[material.conversion]
enabled = true
lambda_minus = 0
lambda_plus = 0.2
decay = 0.1
)");
  const MaterialSpec& material = scene.material;
  EXPECT_EQ(material.model, "fung");
  EXPECT_EQ(material.c2, 2000.0);
  EXPECT_EQ(material.c3, 1.5);
  EXPECT_TRUE(material.conversion.enabled);
  EXPECT_EQ(material.conversion.lambda_minus, 0.0);
  EXPECT_EQ(material.conversion.lambda_plus, 0.2);
  EXPECT_EQ(material.conversion.decay, 0.1);
}

TEST(Scene, MooneyRivlinReadsC2) {
  const Scene scene =
      parse(std::string(kBoxScene) + "[material]\nmodel = \"mooney_rivlin\"\nc2 = 5e4\n");
  EXPECT_EQ(scene.material.c2, 5e4);
}

// c2 and c3 set to nonzero for a model that ignores them mean a forgotten
// material.model: an error that names the key and the models using it.
TEST(Scene, ParameterOfAnotherModelIsRejected) {
  expect_has(error_of(std::string(kBoxScene) + "[material]\nc2 = 100\n"),
             "scene.toml:4: material.c2 is used only by \"mooney_rivlin\" and \"fung\", but "
             "material.model is \"neo_hookean\" (set material.c2 to 0 or change the model)");
  expect_has(
      error_of(std::string(kBoxScene) + "[material]\nmodel = \"mooney_rivlin\"\nc2 = 1\nc3 = 2\n"),
      "scene.toml:6: material.c3 is used only by \"fung\", but material.model is "
      "\"mooney_rivlin\"");
  // Zero, the default, is accepted with any model.
  EXPECT_EQ(parse(std::string(kBoxScene) + "[material]\nmodel = \"stvk\"\nc2 = 0\nc3 = 0\n")
                .material.model,
            "stvk");
}

TEST(Scene, ReadsQuasistatic) {
  EXPECT_TRUE(parse(std::string(kBoxScene) + "[time]\nquasistatic = true\n").time.quasistatic);
  EXPECT_FALSE(parse(std::string(kBoxScene) + "[time]\nquasistatic = false\n").time.quasistatic);
}

TEST(Scene, ReadsAnInlineFixedMotion) {
  const Scene scene = parse(std::string(kBoxScene) + R"(
[[fixed]]
box_max = [1, 1, 1]
motion = { kind = "translate", velocity = [0, 0.1, 0], until = 2 }
)");
  ASSERT_EQ(scene.fixed.size(), 1u);
  const Motion& motion = scene.fixed[0].motion;
  const Motion defaults;
  EXPECT_EQ(motion.kind, "translate");
  EXPECT_EQ(motion.velocity, (Vec3{0, 0.1, 0}));
  EXPECT_EQ(motion.until, 2.0);
  EXPECT_EQ(motion.axis, defaults.axis);
  EXPECT_EQ(motion.centre, defaults.centre);
  EXPECT_EQ(motion.angular_velocity, defaults.angular_velocity);
}

TEST(Scene, ReadsEveryKeyOfAFixedMotionTable) {
  const Scene scene = parse(std::string(kBoxScene) + R"(
[[fixed]]
box_min = [0, 0, 0]
box_max = [1, 1, 1]
axes = "xz"
[fixed.motion]
kind = "rotate"
velocity = [1, 2, 3]
axis = [0, 0, 1]
centre = [0.5, 0.5, 0]
angular_velocity = 3.14
until = 0

[[fixed]]
box_max = [2, 2, 2]
)");
  ASSERT_EQ(scene.fixed.size(), 2u);
  EXPECT_EQ(scene.fixed[0].axes, "xz");
  const Motion& motion = scene.fixed[0].motion;
  EXPECT_EQ(motion.kind, "rotate");
  EXPECT_EQ(motion.velocity, (Vec3{1, 2, 3}));
  EXPECT_EQ(motion.axis, (Vec3{0, 0, 1}));
  EXPECT_EQ(motion.centre, (Vec3{0.5, 0.5, 0}));
  EXPECT_EQ(motion.angular_velocity, 3.14);
  EXPECT_EQ(motion.until, 0.0);
  // The second region has no motion table: it is held at rest.
  EXPECT_EQ(scene.fixed[1].motion.kind, "none");
  EXPECT_EQ(scene.fixed[1].motion.until, Motion{}.until);
}

TEST(Scene, ReadsEveryKeyOfTheLoads) {
  const Scene scene = parse(std::string(kBoxScene) + R"(
[[load]]
box_min = [0, 0.9, 0]
box_max = [1, 1, 1]
force = [0, 100, 0]
ramp = 0.5

[[load]]
force = [-1, 0, 2.5]
)");
  ASSERT_EQ(scene.loads.size(), 2u);
  EXPECT_EQ(scene.loads[0].box_min, (Vec3{0, 0.9, 0}));
  EXPECT_EQ(scene.loads[0].box_max, (Vec3{1, 1, 1}));
  EXPECT_EQ(scene.loads[0].force, (Vec3{0, 100, 0}));
  EXPECT_EQ(scene.loads[0].ramp, 0.5);
  const LoadRegion defaults;
  EXPECT_EQ(scene.loads[1].box_min, defaults.box_min);
  EXPECT_EQ(scene.loads[1].box_max, defaults.box_max);
  EXPECT_EQ(scene.loads[1].force, (Vec3{-1, 0, 2.5}));
  EXPECT_EQ(scene.loads[1].ramp, defaults.ramp);
  EXPECT_TRUE(scene.fixed.empty());
}

TEST(Scene, ReadsEveryKeyOfABoxScene) {
  const Scene scene = parse(R"(
[mesh]
generator = "box"
[mesh.box]
cells = [2, 3, 4]
size = [1, 0.5, 0.25]
origin = [-0.5, 0, 1]
tets_per_cell = 5
)");
  EXPECT_EQ(scene.mesh.generator, "box");
  EXPECT_EQ(scene.mesh.box.cells, (std::array<int, 3>{2, 3, 4}));
  EXPECT_EQ(scene.mesh.box.size, (Vec3{1, 0.5, 0.25}));
  EXPECT_EQ(scene.mesh.box.origin, (Vec3{-0.5, 0, 1}));
  EXPECT_EQ(scene.mesh.box.tets_per_cell, 5);
}

TEST(Scene, ReadsAMeshFileWithItsScale) {
  const Scene scene = parse("[mesh]\nfile = \"meshes/bunny.msh\"\nscale = 0.01\n");
  EXPECT_EQ(scene.mesh.generator, "");
  EXPECT_EQ(scene.mesh.file, "meshes/bunny.msh");  // parse_scene: relative to the cwd
  EXPECT_EQ(scene.mesh.scale, 0.01);
}

TEST(Scene, PresetSetsTheHelixResolution) {
  const Scene scene = parse(std::string(kHelixScene) + "[mesh.helix]\npreset = \"82k\"\n");
  EXPECT_EQ(scene.mesh.helix.resolution, double_helix_preset_resolution("82k"));
}

TEST(Scene, UnknownPresetIsNamedWithItsLine) {
  const std::string message =
      error_of(std::string(kHelixScene) + "[mesh.helix]\npreset = \"99k\"\n");
  expect_has(message, "scene.toml:4: mesh.helix.preset");
  expect_has(message, "99k");
}

TEST(Scene, IntegersAreAcceptedAsFloats) {
  const Scene scene = parse(std::string(kBoxScene) + "[material]\nyoung = 200000\n");
  EXPECT_EQ(scene.material.young, 2e5);
}

// ------------------------------------------------------------ unknown keys

TEST(Scene, UnknownKeySuggestsTheClosestKey) {
  const std::string message = error_of(std::string(kBoxScene) + "[solver]\niteration = 3\n");
  expect_has(message,
             "scene.toml:4: unknown key 'solver.iteration' (did you mean 'solver.iterations'?)");
}

TEST(Scene, UnknownKeyFarFromAnyKeyHasNoSuggestion) {
  const std::string message = error_of(std::string(kBoxScene) + "[solver]\nwarp_speed = 9\n");
  expect_has(message, "scene.toml:4: unknown key 'solver.warp_speed'");
  EXPECT_EQ(message.find("did you mean"), std::string::npos) << message;
}

TEST(Scene, UnknownTableSuggestsTheClosestTable) {
  const std::string message = error_of(std::string(kBoxScene) + "[solvr]\niterations = 3\n");
  expect_has(message, "unknown key 'solvr' (did you mean 'solver'?)");
}

TEST(Scene, UnknownKeyInsideFixedNamesTheEntry) {
  const std::string message =
      error_of(std::string(kBoxScene) + "[[fixed]]\naxes = \"y\"\n[[fixed]]\naxis = \"x\"\n");
  expect_has(message, "scene.toml:6: unknown key 'fixed.1.axis' (did you mean 'fixed.1.axes'?)");
}

TEST(Scene, UnknownKeyInsideMotionSuggestsTheCloseOne) {
  const std::string table =
      std::string(kBoxScene) + "[[fixed]]\naxes = \"y\"\n[fixed.motion]\nknd = \"rotate\"\n";
  expect_has(
      error_of(table),
      "scene.toml:6: unknown key 'fixed.0.motion.knd' (did you mean 'fixed.0.motion.kind'?)");
  const std::string inline_table =
      std::string(kBoxScene) +
      "[[fixed]]\n[[fixed]]\nmotion = { kind = \"rotate\", axsi = [1, 0, 0] }\n";
  expect_has(
      error_of(inline_table),
      "scene.toml:5: unknown key 'fixed.1.motion.axsi' (did you mean 'fixed.1.motion.axis'?)");
  expect_has(error_of(std::string(kBoxScene) + "[[fixed]]\n[fixed.motoin]\nkind = \"rotate\"\n"),
             "unknown key 'fixed.0.motoin' (did you mean 'fixed.0.motion'?)");
}

TEST(Scene, UnknownKeyInsideLoadNamesTheEntry) {
  expect_has(error_of(std::string(kBoxScene) + "[[load]]\n[[load]]\nforse = [0, 1, 0]\n"),
             "scene.toml:5: unknown key 'load.1.forse' (did you mean 'load.1.force'?)");
  // Each array has its own keys: axes belongs to [[fixed]] only.
  expect_has(error_of(std::string(kBoxScene) + "[[load]]\naxes = \"y\"\n"),
             "scene.toml:4: unknown key 'load.0.axes'");
  expect_has(error_of(std::string(kBoxScene) + "[[loads]]\nforce = [0, 1, 0]\n"),
             "unknown key 'loads' (did you mean 'load'?)");
}

TEST(Scene, UnknownKeyInsideMaterialConversion) {
  expect_has(error_of(std::string(kBoxScene) + "[material.conversion]\nlambda_mins = 0.1\n"),
             "scene.toml:4: unknown key 'material.conversion.lambda_mins' (did you mean "
             "'material.conversion.lambda_minus'?)");
  expect_has(error_of(std::string(kBoxScene) + "[material]\nc4 = 1\n"),
             "unknown key 'material.c4' (did you mean 'material.c2'?)");
}

TEST(Scene, UnknownKeyInsideMeshHelix) {
  const std::string message =
      error_of(std::string(kHelixScene) + "[mesh.helix]\ntube_radiu = 0.1\n");
  expect_has(message,
             "scene.toml:4: unknown key 'mesh.helix.tube_radiu' "
             "(did you mean 'mesh.helix.tube_radius'?)");
}

TEST(Scene, UnknownTopLevelKey) {
  expect_has(error_of("gravty = [0, 0, 0]\n" + std::string(kBoxScene)),
             "scene.toml:1: unknown key 'gravty' (did you mean 'gravity'?)");
}

TEST(Scene, QuotedKeyWithADotIsNotANestedKey) {
  expect_has(error_of("\"solver.rho\" = 0.5\n" + std::string(kBoxScene)),
             "scene.toml:1: unknown key 'solver.rho'");
}

TEST(Scene, TopLevelKeyBelowATableIsExplained) {
  expect_has(error_of(std::string(kBoxScene) + "gravity = [0, 0, -9.81]\n"),
             "scene.toml:3: unknown key 'mesh.gravity' ('gravity' is a top-level key: write it "
             "above the first [table])");
}

// ------------------------------------------------------------- wrong types

TEST(Scene, WrongTypeNamesKeyExpectedTypeFoundValueAndLine) {
  std::string text = kBoxScene;  // lines 1-2
  for (int line = 3; line <= 10; ++line) text += "# filler\n";
  text += "[solver]\n";               // line 11
  text += "iterations = \"many\"\n";  // line 12
  expect_has(error_of(text),
             "scene.toml:12: solver.iterations must be an integer, got string \"many\"");
}

TEST(Scene, FloatIsNotAcceptedAsAnInteger) {
  expect_has(error_of(std::string(kBoxScene) + "[time]\nframes = 3.5\n"),
             "scene.toml:4: time.frames must be an integer, got float 3.5");
}

TEST(Scene, StringIsNotANumber) {
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nrho = \"high\"\n"),
             "solver.rho must be a number, got string \"high\"");
}

TEST(Scene, VectorNeedsExactlyThreeNumbers) {
  expect_has(error_of("gravity = [0, -9.81]\n" + std::string(kBoxScene)),
             "scene.toml:1: gravity must be an array of 3 numbers, got array [0, -9.81]");
  expect_has(error_of("gravity = [0, \"down\", 0]\n" + std::string(kBoxScene)),
             "gravity must be an array of 3 numbers, got array [0, \"down\", 0]");
  expect_has(error_of("gravity = -9.81\n" + std::string(kBoxScene)),
             "gravity must be an array of 3 numbers, got float -9.81");
}

TEST(Scene, IntegerVectorRejectsFloats) {
  expect_has(error_of(std::string(kBoxScene) + "[mesh.box]\ncells = [4, 4.5, 4]\n"),
             "scene.toml:4: mesh.box.cells must be an array of 3 integers, got array [4, 4.5, 4]");
}

TEST(Scene, TableKeyHoldingAValue) {
  expect_has(error_of("solver = 3\n" + std::string(kBoxScene)),
             "scene.toml:1: solver must be a table, got integer 3");
  expect_has(error_of("fixed = 3\n" + std::string(kBoxScene)),
             "fixed must be an array of tables ([[fixed]]), got integer 3");
  expect_has(error_of("fixed = [1]\n" + std::string(kBoxScene)),
             "fixed.0 must be a table, got integer 1");
}

TEST(Scene, ArraysAndNestedTablesHoldingAValue) {
  expect_has(error_of("load = 3\n" + std::string(kBoxScene)),
             "scene.toml:1: load must be an array of tables ([[load]]), got integer 3");
  expect_has(error_of("load = [[0, 1, 0]]\n" + std::string(kBoxScene)),
             "load.0 must be a table, got array [0, 1, 0]");
  expect_has(error_of(std::string(kBoxScene) + "[[fixed]]\nmotion = \"rotate\"\n"),
             "scene.toml:4: fixed.0.motion must be a table, got string \"rotate\"");
}

TEST(Scene, BooleansAreNotNumbersOrStrings) {
  expect_has(error_of(std::string(kBoxScene) + "[material.conversion]\nenabled = \"yes\"\n"),
             "scene.toml:4: material.conversion.enabled must be a boolean (true or false), got "
             "string \"yes\"");
  expect_has(error_of(std::string(kBoxScene) + "[time]\nquasistatic = 1\n"),
             "scene.toml:4: time.quasistatic must be a boolean (true or false), got integer 1");
  expect_has(error_of(std::string(kBoxScene) + "[time]\nquasistatic = \"true\"\n"),
             "time.quasistatic must be a boolean (true or false), got string \"true\"");
  expect_has(error_of(std::string(kBoxScene) + "[time]\nframes = true\n"),
             "time.frames must be an integer, got boolean true");
}

TEST(Scene, WrongTypesInsideArrayEntriesNameTheEntry) {
  expect_has(error_of(std::string(kBoxScene) + "[[load]]\nforce = [0, 1]\n"),
             "scene.toml:4: load.0.force must be an array of 3 numbers, got array [0, 1]");
  expect_has(error_of(std::string(kBoxScene) + "[[load]]\nramp = \"slow\"\n"),
             "load.0.ramp must be a number, got string \"slow\"");
  expect_has(error_of(std::string(kBoxScene) + "[[fixed]]\n[fixed.motion]\nkind = 1\n"),
             "scene.toml:5: fixed.0.motion.kind must be a string, got integer 1");
  expect_has(
      error_of(std::string(kBoxScene) + "[[fixed]]\nmotion = { angular_velocity = \"fast\" }\n"),
      "fixed.0.motion.angular_velocity must be a number, got string \"fast\"");
}

TEST(Scene, NumbersMustBeFinite) {
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nrho = nan\n"),
             "scene.toml:4: solver.rho must be a finite number, got float nan");
  expect_has(error_of("gravity = [0, -inf, 0]\n" + std::string(kBoxScene)),
             "gravity must be an array of 3 finite numbers");
}

// ------------------------------------------------------------------ ranges

struct RangeCase {
  std::string entry;     // TOML appended to the box scene (from line 3)
  std::string expected;  // a part of the message
};

TEST(Scene, RangesNameTheKeyAndTheLine) {
  const std::vector<RangeCase> cases = {
      {"[time]\ndt = 0", "scene.toml:4: time.dt must be > 0, got 0"},
      {"[time]\nframes = -1", "time.frames must be >= 0, got -1"},
      {"[solver]\niterations = 0", "scene.toml:4: solver.iterations must be >= 1, got 0"},
      {"[solver]\nrho = 1.0", "solver.rho must be in [0, 1), got 1"},
      {"[solver]\nrho = -0.1", "solver.rho must be in [0, 1), got -0.1"},
      {"[solver]\nchebyshev_parameters = \"fixed\"\nchebyshev_delay = -1",
       "solver.chebyshev_delay must be >= 0, got -1"},
      {"[solver]\naccuracy = 1", "scene.toml:4: solver.accuracy must be in [0, 1)"},
      {"[solver]\naccuracy = -1e-3", "solver.accuracy must be in [0, 1)"},
      {"[solver]\nspectrum_steps = 1", "solver.spectrum_steps must be in [2, 1000], got 1"},
      {"[solver]\nspectrum_interval = -1", "solver.spectrum_interval must be >= 0"},
      {"[solver]\nspectrum_margin = -0.1", "solver.spectrum_margin must be in [0, 10]"},
      {"[solver]\nhessian_interval = 0", "solver.hessian_interval must be >= 1, got 0"},
      {"[solver]\ncheck_interval = 0", "solver.check_interval must be >= 1, got 0"},
      {"[solver]\ngamma = 1", "solver.gamma must be in (0, 1), got 1"},
      {"[solver]\ngamma = 0", "solver.gamma must be in (0, 1), got 0"},
      {"[solver]\nalpha_min = 0", "solver.alpha_min must be > 0, got 0"},
      {"[solver]\nalpha_min = 0.5\nalpha_max = 0.1",
       "scene.toml:4: solver.alpha_min (0.5) must not exceed solver.alpha_max (0.1)"},
      {"[solver]\neta = -0.5", "solver.eta must be >= 0, got -0.5"},
      {"[solver]\ndamping = -1", "solver.damping must be >= 0, got -1"},
      {"[material]\nyoung = 0", "material.young must be > 0, got 0"},
      {"[material]\npoisson = 0.5", "material.poisson must be in (-1, 0.5), got 0.5"},
      {"[material]\npoisson = -1", "material.poisson must be in (-1, 0.5), got -1"},
      {"[material]\ndensity = -1000", "material.density must be > 0, got -1000"},
      {"[material]\nmodel = \"mooney_rivlin\"\nc2 = -1", "material.c2 must be >= 0, got -1"},
      {"[material]\nmodel = \"fung\"\nc3 = -0.5", "material.c3 must be >= 0, got -0.5"},
      {"[material.conversion]\nlambda_minus = -0.1",
       "scene.toml:4: material.conversion.lambda_minus must be >= 0, got -0.1"},
      {"[material.conversion]\nlambda_minus = 0.2",
       "scene.toml:4: material.conversion.lambda_minus (0.2) must be less than "
       "material.conversion.lambda_plus (0.15)"},
      {"[material.conversion]\nlambda_plus = 0.05",
       "scene.toml:4: material.conversion.lambda_minus (0.05) must be less than "
       "material.conversion.lambda_plus (0.05)"},
      {"[material.conversion]\ndecay = -1", "material.conversion.decay must be >= 0, got -1"},
      {"[material.conversion]\ndecay = inf",
       "material.conversion.decay must be a finite number, got float inf"},
      {"[output]\nevery = 0", "output.every must be >= 1, got 0"},
      {"[output]\ndir = \"\"", "output.dir must not be empty"},
      {"[mesh.box]\ncells = [4, 0, 4]", "mesh.box.cells must be at least 1 along each axis, got 0"},
      {"[mesh.box]\ntets_per_cell = 4", "mesh.box.tets_per_cell must be 5 or 6, got 4"},
      {"[[fixed]]\nbox_min = [0, 2, 0]\nbox_max = [1, 1, 1]",
       "scene.toml:4: fixed.0.box_min must not exceed fixed.0.box_max, but its y is 2 > 1"},
      {"[[fixed]]\naxes = \"\"", "fixed.0.axes must name each of x, y, z at most once"},
      {"[[fixed]]\naxes = \"xx\"", "fixed.0.axes must name each of x, y, z at most once"},
      {"[[fixed]]\naxes = \"xw\"", "got \"xw\""},
      {"[[fixed]]\n[fixed.motion]\nuntil = -1",
       "scene.toml:5: fixed.0.motion.until must be >= 0, got -1"},
      {"[[fixed]]\nmotion = { kind = \"rotate\", axis = [0, 0, 0] }",
       "scene.toml:4: fixed.0.motion.axis must not be [0, 0, 0] when fixed.0.motion.kind is "
       "\"rotate\""},
      {"[[load]]\nbox_min = [0, 0, 3]\nbox_max = [1, 1, 1]",
       "scene.toml:4: load.0.box_min must not exceed load.0.box_max, but its z is 3 > 1"},
      {"[[load]]\n[[load]]\nramp = -0.5", "scene.toml:5: load.1.ramp must be >= 0, got -0.5"},
  };
  for (const RangeCase& c : cases) {
    SCOPED_TRACE(c.entry);
    expect_has(error_of(kBoxScene + c.entry + "\n"), c.expected);
  }
  expect_has(error_of("[mesh]\nfile = \"a.msh\"\nscale = 0\n"),
             "scene.toml:3: mesh.scale must be > 0, got 0");
  expect_has(error_of(std::string(kHelixScene) + "[mesh.helix]\ntube_radius = -0.1\n"),
             "mesh.helix.tube_radius must be > 0, got -0.1");
}

TEST(Scene, MethodKeysAreChecked) {
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nphase_rho = [0.9, 0.95]\n"),
             "solver.phase_lengths needs one length fewer than solver.phase_rho has phases");
  expect_has(
      error_of(std::string(kBoxScene) + "[solver]\nphase_rho = [0.9, 1.5]\nphase_lengths = [10]\n"),
      "solver.phase_rho must be in [0, 1) for every phase, got 1.5");
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nphase_rho = [0.9, \"a\"]\n"),
             "solver.phase_rho must be an array of finite numbers");
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nmethod = \"pd_chebyshev\"\n"),
             "solver.method = pd_chebyshev needs material.model = \"arap\"");
  expect_has(error_of(std::string(kBoxScene) +
                      "[material]\nconversion.enabled = true\n[solver]\nmethod = \"newton\"\n"),
             "solver.method = newton needs material.conversion.enabled = false");
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nmethod = \"linear_cg\"\n"),
             "solver.method = linear_cg needs material.model = \"corotated\"");
  expect_has(error_of(std::string(kBoxScene) +
                      "[material]\nmodel = \"corotated\"\n[time]\nquasistatic = true\n"
                      "[solver]\nmethod = \"linear_cg\"\n"),
             "solver.method = linear_cg integrates in time and needs time.quasistatic = false");
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nrayleigh_stiffness = 0.01\n"),
             "solver.rayleigh_stiffness applies to solver.method = linear_cg only");
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nlinear_cg_guess = \"last\"\n"),
             "solver.linear_cg_guess must be one of \"zero\", \"velocity\", \"euler\", got "
             "\"last\"");
  expect_has(error_of(std::string(kBoxScene) + "[solver]\npolar_sweeps = 0\n"),
             "solver.polar_sweeps must be >= 1, got 0");
  const Scene linear = parse_scene(std::string(kBoxScene) +
                                       "[material]\nmodel = \"corotated\"\n[solver]\n"
                                       "method = \"linear_cg\"\nlinear_cg_preconditioner = "
                                       "\"mass\"\nrayleigh_stiffness = 0.02\n",
                                   "scene.toml");
  EXPECT_EQ(linear.solver.linear_cg_preconditioner, "mass");
  EXPECT_EQ(linear.solver.rayleigh_stiffness, 0.02);
  const Scene phases = parse_scene(
      std::string(kBoxScene) + "[solver]\nphase_rho = [0.9, 0.99]\nphase_lengths = [24]\n",
      "scene.toml");
  EXPECT_EQ(phases.solver.phase_rho, (std::vector<double>{0.9, 0.99}));
  EXPECT_EQ(phases.solver.phase_lengths, (std::vector<int>{24}));
}

// Another P^-1 than Jacobi's for the methods that precondition, newton's CG
// among them; not for gd, nor newton's direct and PETSc solvers.
TEST(Scene, PreconditionerFollowsTheMethod) {
  const std::string box = kBoxScene;
  EXPECT_NO_THROW(parse(box + "[solver]\nmethod = \"newton\"\npreconditioner = \"multilevel\"\n"));
  expect_has(error_of(box + "[solver]\nmethod = \"gd\"\npreconditioner = \"multilevel\"\n"),
             "solver.preconditioner = \"multilevel\" preconditions chebyshev, jacobi_gd, nesterov, "
             "ncg, lbfgs, linear_cg and newton's CG, not gd");
  expect_has(error_of(box + "[solver]\nmethod = \"newton\"\nnewton_solver = \"ldlt\"\n"
                            "preconditioner = \"multilevel\"\n"),
             "solver.preconditioner = \"multilevel\" preconditions newton's CG "
             "(solver.newton_solver = \"cg\"), not solver.newton_solver = \"ldlt\"");
}

// Automatic Chebyshev parameters unless the scene sets a fixed one; a fixed
// key beside an explicit "auto" names the key, and so does chebyshev_delay
// without fixed parameters.
TEST(Scene, ChebyshevParametersFollowTheKeysSet) {
  EXPECT_EQ(parse(kBoxScene).solver.chebyshev_parameters, "auto");
  for (const char* key : {"rho = 0.99", "alpha_max = 0.8", "phase_rho = [0.99]"}) {
    SCOPED_TRACE(key);
    const Scene fixed = parse(std::string(kBoxScene) + "[solver]\n" + key + "\n");
    EXPECT_EQ(fixed.solver.chebyshev_parameters, "fixed");
  }
  const Scene said = parse(std::string(kBoxScene) + "[solver]\nchebyshev_parameters = \"fixed\"\n");
  EXPECT_EQ(said.solver.chebyshev_parameters, "fixed");
  expect_has(error_of(std::string(kBoxScene) +
                      "[solver]\nchebyshev_parameters = \"auto\"\nalpha_max = 0.5\n"),
             "scene.toml:5: solver.alpha_max is a fixed Chebyshev parameter, but "
             "solver.chebyshev_parameters = \"auto\" (scene.toml:4)");
  // An override's "auto" wins over the file's fixed keys (a study case).
  const Scene overridden =
      parse_scene(std::string(kBoxScene) + "[solver]\nrho = 0.9\nchebyshev_delay = 4\n",
                  "scene.toml", {"solver.chebyshev_parameters=\"auto\""});
  EXPECT_EQ(overridden.solver.chebyshev_parameters, "auto");
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nchebyshev_delay = 3\n"),
             "scene.toml:4: solver.chebyshev_delay applies to fixed Chebyshev parameters");
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nchebyshev_parameters = \"tuned\"\n"),
             "solver.chebyshev_parameters must be one of \"auto\", \"fixed\"");
  // Every method counts by a target (issue 24).
  for (const char* method : {"gd", "jacobi_gd", "nesterov", "ncg", "lbfgs", "newton", "linear_cg",
                             "pd_chebyshev", "tao_bncg", "tao_blmvm"}) {
    SCOPED_TRACE(method);
    std::string text =
        std::string(kBoxScene) + "[solver]\nmethod = \"" + method + "\"\naccuracy = 0.01\n";
    if (std::string(method) == "linear_cg") text += "[material]\nmodel = \"corotated\"\n";
    if (std::string(method) == "pd_chebyshev") text += "[material]\nmodel = \"arap\"\n";
    const Scene accurate = parse(text);
    EXPECT_EQ(accurate.solver.accuracy, 0.01);
    EXPECT_EQ(accurate.solver.iterations, 1000) << "the cap of a step with a target";
  }
  expect_has(error_of(std::string(kBoxScene) +
                      "[solver]\naccuracy = 0.01\nphase_rho = [0.9, 0.99]\nphase_lengths = [8]\n"),
             "solver.accuracy counts iterations by one Chebyshev bound");
  const Scene target = parse(std::string(kBoxScene) +
                             "[solver]\naccuracy = 1e-3\n"
                             "spectrum_steps = 30\nspectrum_interval = 0\n"
                             "spectrum_margin = 0.2\n");
  EXPECT_EQ(target.solver.accuracy, 1e-3);
  EXPECT_EQ(target.solver.spectrum_steps, 30);
  EXPECT_EQ(target.solver.spectrum_interval, 0);
  EXPECT_EQ(target.solver.spectrum_margin, 0.2);
}

// Without solver keys Chebyshev runs each step to the default accuracy
// under a cap that does not bind; `iterations` alone keeps a fixed count,
// and methods that cannot count by an accuracy keep theirs.
TEST(Scene, StepsRunToTheDefaultAccuracyUnlessTheSceneSaysOtherwise) {
  const auto rule = [](const std::string& solver, const Overrides& overrides = {}) {
    const SolverSpec spec = parse(std::string(kBoxScene) + "[solver]\n" + solver, overrides).solver;
    return std::make_pair(spec.accuracy, spec.iterations);
  };
  const SolverSpec defaults;
  EXPECT_EQ(rule(""), std::make_pair(kDefaultAccuracy, kDefaultAccuracyCap));
  EXPECT_EQ(rule("iterations = 64\n"), std::make_pair(0.0, 64));
  EXPECT_EQ(rule("", {"solver.iterations=64"}), std::make_pair(0.0, 64));
  EXPECT_EQ(rule("accuracy = 0\n"), std::make_pair(0.0, defaults.iterations));
  EXPECT_EQ(rule("accuracy = 1e-3\n"), std::make_pair(1e-3, kDefaultAccuracyCap));
  EXPECT_EQ(rule("accuracy = 1e-3\niterations = 300\n"), std::make_pair(1e-3, 300));
  EXPECT_EQ(rule("rho = 0.96\n"), std::make_pair(kDefaultAccuracy, kDefaultAccuracyCap));
  EXPECT_EQ(rule("phase_rho = [0.9, 0.99]\nphase_lengths = [8]\n"),
            std::make_pair(0.0, defaults.iterations));
  EXPECT_EQ(rule("method = \"ncg\"\n"), std::make_pair(0.0, defaults.iterations));
}

// The default accuracy changes no job: each parses, and each that sets a
// count or a target runs what it ran before (the count without a target, 96
// unless given; the target with the cap given).
TEST(Scene, EveryJobKeepsItsIterationRule) {
  int checked = 0;
  for (const auto& entry :
       fs::recursive_directory_iterator(fs::path(DESCENT_SOURCE_DIR) / "jobs")) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().string());
    const SolverSpec spec = load_scene(entry.path().string()).solver;
    const toml::table file = toml::parse_file(entry.path().string());
    const std::optional<int> iterations = file["solver"]["iterations"].value<int>();
    const std::optional<double> accuracy = file["solver"]["accuracy"].value<double>();
    if (!iterations && !accuracy) continue;  // the default target: the test above
    EXPECT_EQ(spec.accuracy, accuracy.value_or(0.0));
    EXPECT_EQ(spec.iterations, iterations.value_or(SolverSpec{}.iterations));
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

TEST(Scene, ChoicesListTheValidNames) {
  expect_has(error_of(std::string(kBoxScene) + "[material]\nmodel = \"hookean\"\n"),
             "scene.toml:4: material.model must be one of \"stvk\", \"neo_hookean\", "
             "\"mooney_rivlin\", \"fung\", \"corotated\", \"arap\", got \"hookean\"");
  expect_has(error_of(std::string(kBoxScene) + "[[fixed]]\nmotion = { kind = \"spin\" }\n"),
             "scene.toml:4: fixed.0.motion.kind must be one of \"none\", \"translate\", "
             "\"rotate\", got \"spin\"");
  expect_has(error_of(std::string(kBoxScene) + "[solver]\nmethod = \"jacobi\"\n"),
             "solver.method must be one of \"chebyshev\", \"gd\", \"jacobi_gd\", \"nesterov\", "
             "\"ncg\", \"lbfgs\", \"newton\", \"pd_chebyshev\", \"linear_cg\", \"tao_bncg\", "
             "\"tao_blmvm\", got \"jacobi\"");
  expect_has(error_of(std::string(kBoxScene) + "[solver]\ninit = \"guess\"\n"),
             "solver.init must be one of \"constant_acceleration\", \"position\", \"velocity\"");
  expect_has(error_of("[mesh]\ngenerator = \"sphere\"\n"),
             "scene.toml:2: mesh.generator must be one of \"double_helix\", \"box\", \"ball\", "
             "\"car\", got \"sphere\"");
}

// ------------------------------------------------------------- mesh source

TEST(Scene, MeshNeedsExactlyOneOfGeneratorAndFile) {
  expect_has(error_of("[mesh]\nscale = 2\n"), "set mesh.generator");
  const std::string both = error_of("[mesh]\ngenerator = \"box\"\nfile = \"a.msh\"\n");
  expect_has(both, "scene.toml:3: mesh.file and mesh.generator exclude each other");
  expect_has(error_of("[mesh]\nfile = \"\"\n"), "mesh.file must not be empty");
}

TEST(Scene, ParameterTableMustMatchTheGenerator) {
  expect_has(error_of(std::string(kBoxScene) + "[mesh.helix]\nturns = 3\n"),
             "scene.toml:3: mesh.helix goes with mesh.generator = \"double_helix\", but "
             "mesh.generator is \"box\"");
  expect_has(error_of(std::string(kHelixScene) + "[mesh.box]\ncells = [1, 1, 1]\n"),
             "mesh.box goes with mesh.generator = \"box\"");
  expect_has(error_of("[mesh]\nfile = \"a.msh\"\n[mesh.helix]\nturns = 3\n"),
             "the mesh is read from mesh.file");
}

TEST(Scene, PresetAndResolutionExcludeEachOther) {
  expect_has(
      error_of(std::string(kHelixScene) + "[mesh.helix]\npreset = \"41k\"\nresolution = 2\n"),
      "scene.toml:5: mesh.helix.resolution and mesh.helix.preset exclude each other");
}

// ------------------------------------------------------- syntax and files

TEST(Scene, SyntaxErrorGivesLineAndColumn) {
  const std::string message = error_of(std::string(kBoxScene) + "[solver]\niterations = = 3\n");
  EXPECT_EQ(message.rfind("scene.toml:4:", 0), 0u) << message;
  // file:line:column: then toml++'s description
  EXPECT_GT(message.size(), std::string("scene.toml:4:14: ").size()) << message;
}

TEST(Scene, MissingFileIsNamed) {
  const std::string path = "/nonexistent/descent/scene.toml";
  try {
    load_scene(path);
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    expect_has(error.what(), path);
  }
}

TEST(Scene, LoadSceneRecordsItsSource) {
  const TempDir dir;
  const fs::path file = dir.write("scene.toml", kBoxScene);
  EXPECT_EQ(load_scene(file.string()).source, file.string());
}

TEST(Scene, FileErrorsNameTheFile) {
  const TempDir dir;
  const fs::path file = dir.write("bad.toml", std::string(kBoxScene) + "[solver]\nrho = 2\n");
  try {
    load_scene(file.string());
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    expect_has(error.what(), file.string() + ":4: solver.rho");
  }
}

TEST(Scene, RelativeMeshFileResolvesAgainstTheSceneFolder) {
  const TempDir dir;
  const fs::path scene_file =
      dir.write("scenes/bunny.toml", "[mesh]\nfile = \"../meshes/bunny.msh\"\n");
  EXPECT_EQ(load_scene(scene_file.string()).mesh.file, (dir.path() / "meshes/bunny.msh").string());
}

TEST(Scene, AbsoluteMeshFileIsKept) {
  const TempDir dir;
  const fs::path scene_file = dir.write("scene.toml", "[mesh]\nfile = \"/data/bunny.msh\"\n");
  EXPECT_EQ(load_scene(scene_file.string()).mesh.file, "/data/bunny.msh");
}

TEST(Scene, MeshFileFromTheCommandLineStaysRelativeToTheCurrentFolder) {
  const TempDir dir;
  const fs::path scene_file = dir.write("scenes/a.toml", "[mesh]\nfile = \"a.msh\"\n");
  EXPECT_EQ(load_scene(scene_file.string(), {"mesh.file=\"b.msh\""}).mesh.file, "b.msh");
}

TEST(Scene, OutputDirIsKeptAsGiven) {
  const TempDir dir;
  const fs::path scene_file =
      dir.write("scenes/a.toml", std::string(kBoxScene) + "[output]\ndir = \"runs/a\"\n");
  EXPECT_EQ(load_scene(scene_file.string()).output.dir, "runs/a");
}

// --------------------------------------------------------------- overrides

TEST(SceneOverrides, ScalarReplacesTheFileValue) {
  const Scene scene =
      parse(std::string(kBoxScene) + "[solver]\niterations = 96\n", {"solver.iterations=64"});
  EXPECT_EQ(scene.solver.iterations, 64);
}

TEST(SceneOverrides, AddsKeysAndTablesTheFileLacks) {
  const Scene scene = parse(kBoxScene, {"solver.rho=0.5", "mesh.box.cells=[1, 2, 3]"});
  EXPECT_EQ(scene.solver.rho, 0.5);
  EXPECT_EQ(scene.mesh.box.cells, (std::array<int, 3>{1, 2, 3}));
}

TEST(SceneOverrides, Vector) {
  EXPECT_EQ(parse(kBoxScene, {"gravity=[0,0,-9.81]"}).gravity, (Vec3{0, 0, -9.81}));
}

TEST(SceneOverrides, QuotedString) {
  EXPECT_EQ(parse("[mesh]\nfile = \"a.msh\"\n", {"mesh.file=\"b c.msh\""}).mesh.file, "b c.msh");
  EXPECT_EQ(parse(kBoxScene, {"material.model=\"neo_hookean\""}).material.model, "neo_hookean");
}

TEST(SceneOverrides, BareWordIsAString) {
  EXPECT_EQ(parse(kBoxScene, {"output.dir=runs/a"}).output.dir, "runs/a");
  EXPECT_EQ(parse(kBoxScene, {"solver.init=position"}).solver.init, "position");
}

TEST(SceneOverrides, LaterOverrideWins) {
  EXPECT_EQ(parse(kBoxScene, {"time.frames=10", "time.frames=20"}).time.frames, 20);
}

TEST(SceneOverrides, FixedEntriesByIndex) {
  const std::string text =
      std::string(kBoxScene) + "[[fixed]]\nbox_min = [0, 0, 0]\nbox_max = [1, 1, 1]\n";
  const Scene scene = parse(text, {"fixed.0.axes=\"y\"", "fixed.1.box_max=[2, 2, 2]"});
  ASSERT_EQ(scene.fixed.size(), 2u);
  EXPECT_EQ(scene.fixed[0].axes, "y");
  EXPECT_EQ(scene.fixed[0].box_max, (Vec3{1, 1, 1}));
  EXPECT_EQ(scene.fixed[1].box_max, (Vec3{2, 2, 2}));  // index == size appends
  EXPECT_EQ(scene.fixed[1].axes, "xyz");
}

TEST(SceneOverrides, FixedEntryWithoutAnyInTheFile) {
  const Scene scene = parse(kBoxScene, {"fixed.0.axes=y"});
  ASSERT_EQ(scene.fixed.size(), 1u);
  EXPECT_EQ(scene.fixed[0].axes, "y");
}

TEST(SceneOverrides, FixedIndexPastTheEnd) {
  const std::string message = error_of(kBoxScene, {"fixed.2.axes=y"});
  expect_has(message, "--set fixed.2.axes=y: fixed has 0 entries");
}

TEST(SceneOverrides, LoadEntryWithoutAnyInTheFile) {
  const Scene scene = parse(kBoxScene, {"load.0.force=[0,0,5]"});
  ASSERT_EQ(scene.loads.size(), 1u);
  EXPECT_EQ(scene.loads[0].force, (Vec3{0, 0, 5}));
  EXPECT_EQ(scene.loads[0].ramp, LoadRegion{}.ramp);
}

TEST(SceneOverrides, LoadEntriesByIndex) {
  const std::string text = std::string(kBoxScene) + "[[load]]\nforce = [0, 1, 0]\nramp = 1\n";
  const Scene scene = parse(text, {"load.0.force=[0,100,0]", "load.1.ramp=2"});
  ASSERT_EQ(scene.loads.size(), 2u);
  EXPECT_EQ(scene.loads[0].force, (Vec3{0, 100, 0}));
  EXPECT_EQ(scene.loads[0].ramp, 1.0);
  EXPECT_EQ(scene.loads[1].ramp, 2.0);  // index == size appends
  EXPECT_EQ(scene.loads[1].force, LoadRegion{}.force);
  expect_has(error_of(text, {"load.3.ramp=1"}),
             "--set load.3.ramp=1: load has 1 entries; load.3 is past its end (load.1 appends "
             "one)");
}

TEST(SceneOverrides, FixedMotionKeys) {
  const std::string text = std::string(kBoxScene) + "[[fixed]]\nbox_max = [1, 1, 1]\n";
  const Scene scene = parse(text, {"fixed.0.motion.kind=\"rotate\"", "fixed.0.motion.axis=[1,0,0]",
                                   "fixed.0.motion.angular_velocity=2"});
  ASSERT_EQ(scene.fixed.size(), 1u);
  EXPECT_EQ(scene.fixed[0].box_max, (Vec3{1, 1, 1}));
  EXPECT_EQ(scene.fixed[0].motion.kind, "rotate");
  EXPECT_EQ(scene.fixed[0].motion.axis, (Vec3{1, 0, 0}));
  EXPECT_EQ(scene.fixed[0].motion.angular_velocity, 2.0);
  // Into an inline motion table of the file, keeping its other keys.
  const std::string inline_motion =
      std::string(kBoxScene) +
      "[[fixed]]\nmotion = { kind = \"translate\", velocity = [0, 1, 0] }\n";
  const Scene changed = parse(inline_motion, {"fixed.0.motion.until=3"});
  EXPECT_EQ(changed.fixed[0].motion.kind, "translate");
  EXPECT_EQ(changed.fixed[0].motion.velocity, (Vec3{0, 1, 0}));
  EXPECT_EQ(changed.fixed[0].motion.until, 3.0);
  // A whole motion as an inline table, appending a region.
  const Scene appended = parse(kBoxScene, {"fixed.0.motion={kind=\"translate\",until=1}"});
  ASSERT_EQ(appended.fixed.size(), 1u);
  EXPECT_EQ(appended.fixed[0].motion.kind, "translate");
  EXPECT_EQ(appended.fixed[0].motion.until, 1.0);
}

TEST(SceneOverrides, MaterialKeys) {
  const Scene scene =
      parse(kBoxScene, {"material.model=mooney_rivlin", "material.c2=3e4",
                        "material.conversion.enabled=true", "material.conversion.lambda_plus=0.3"});
  EXPECT_EQ(scene.material.model, "mooney_rivlin");
  EXPECT_EQ(scene.material.c2, 3e4);
  EXPECT_TRUE(scene.material.conversion.enabled);
  EXPECT_EQ(scene.material.conversion.lambda_plus, 0.3);
  expect_has(error_of(std::string(kBoxScene) + "[material]\nmodel = \"fung\"\nc3 = 2\n",
                      {"material.model=stvk"}),
             "scene.toml:5: material.c3 is used only by \"fung\", but material.model is \"stvk\"");
  expect_has(error_of(kBoxScene, {"material.conversion.enabled=1"}),
             "--set material.conversion.enabled=1: material.conversion.enabled must be a boolean");
}

TEST(SceneOverrides, NewKeysAreCheckedLikeFileEntries) {
  EXPECT_EQ(parse(kBoxScene, {"material.model=\"fung\""}).material.model, "fung");
  EXPECT_TRUE(parse(kBoxScene, {"time.quasistatic=true"}).time.quasistatic);
  expect_has(error_of(kBoxScene, {"material.model=\"hookean\""}),
             "--set material.model=\"hookean\": material.model must be one of \"stvk\", "
             "\"neo_hookean\", \"mooney_rivlin\", \"fung\", \"corotated\", \"arap\"");
  expect_has(error_of(kBoxScene, {"time.quasistatic=yes"}),
             "--set time.quasistatic=yes: time.quasistatic must be a boolean (true or false), got "
             "string \"yes\"");
  expect_has(error_of(kBoxScene, {"fixed.0.motion.knd=rotate"}),
             "--set fixed.0.motion.knd=rotate: unknown key 'fixed.0.motion.knd' (did you mean "
             "'fixed.0.motion.kind'?)");
  expect_has(error_of(kBoxScene, {"fixed.0.motion.kind=rotate", "fixed.0.motion.axis=[0,0,0]"}),
             "--set fixed.0.motion.axis=[0,0,0]: fixed.0.motion.axis must not be [0, 0, 0]");
  expect_has(error_of(kBoxScene, {"load.0.ramp=-1"}),
             "--set load.0.ramp=-1: load.0.ramp must be >= 0, got -1");
  expect_has(error_of(kBoxScene, {"load.0.forse=[0,0,5]"}),
             "--set load.0.forse=[0,0,5]: unknown key 'load.0.forse' (did you mean "
             "'load.0.force'?)");
}

TEST(SceneOverrides, UnknownKeySaysItCameFromSet) {
  expect_has(error_of(kBoxScene, {"solver.iteration=64"}),
             "--set solver.iteration=64: unknown key 'solver.iteration' "
             "(did you mean 'solver.iterations'?)");
  expect_has(error_of(kBoxScene, {"solvr.iterations=64"}),
             "--set solvr.iterations=64: unknown key 'solvr' (did you mean 'solver'?)");
}

TEST(SceneOverrides, WrongTypeSaysItCameFromSet) {
  expect_has(error_of(kBoxScene, {"solver.iterations=many"}),
             "--set solver.iterations=many: solver.iterations must be an integer, got string "
             "\"many\"");
  expect_has(error_of(kBoxScene, {"gravity=[0, 1]"}),
             "--set gravity=[0, 1]: gravity must be an array of 3 numbers");
}

TEST(SceneOverrides, RangeErrorSaysItCameFromSet) {
  expect_has(error_of(kBoxScene, {"solver.rho=1.5"}),
             "--set solver.rho=1.5: solver.rho must be in [0, 1), got 1.5");
}

TEST(SceneOverrides, MalformedOverrides) {
  expect_has(error_of(kBoxScene, {"solver.iterations"}),
             "--set solver.iterations: expected key=value");
  expect_has(error_of(kBoxScene, {"solver..rho=1"}), "is not a dotted key");
  expect_has(error_of(kBoxScene, {"solver.rho="}), "no value");
  expect_has(error_of(kBoxScene, {"gravity=[0, 0"}), "--set gravity=[0, 0: the value is not TOML");
  expect_has(error_of(kBoxScene, {"solver.iterations=3", "solver.iterations.x=1"}),
             "--set solver.iterations.x=1: solver.iterations holds");
}

// An override replaces the file's key that it excludes; two overrides that
// exclude each other are checked after merging, like two lines of a file.
TEST(SceneOverrides, ConflictsAreCheckedAfterMerging) {
  EXPECT_EQ(parse(kBoxScene, {"mesh.file=a.msh"}).mesh.file, "a.msh");
  expect_has(error_of(kBoxScene, {"mesh.file=a.msh", "mesh.generator=box"}),
             "--set mesh.file=a.msh: mesh.file and mesh.generator exclude each other");
}

TEST(Scene, ReadsEveryKeyOfTheObstaclesAndContact) {
  const Scene scene = parse(std::string(kBoxScene) + R"(
[contact]
method = "projection"
distance = 0.002
stiffness = 1e4
smoothing_velocity = 0.01
[[obstacle]]
kind = "plane"
point = [0, -1, 0]
normal = [0, 2, 0]
friction = 0.4
[obstacle.motion]
kind = "translate"
velocity = [0, 0.5, 0]
until = 1.5
[[obstacle]]
kind = "sphere"
centre = [1, 2, 3]
radius = 0.25
[[obstacle]]
kind = "box"
box_min = [-1, -1, -1]
box_max = [1, 0, 1]
)");
  EXPECT_EQ(scene.contact.method, "projection");
  EXPECT_EQ(scene.contact.distance, 0.002);
  EXPECT_EQ(scene.contact.stiffness, 1e4);
  EXPECT_EQ(scene.contact.smoothing_velocity, 0.01);
  ASSERT_EQ(scene.obstacles.size(), 3u);
  EXPECT_EQ(scene.obstacles[0].kind, "plane");
  EXPECT_EQ(scene.obstacles[0].point, (Vec3{0, -1, 0}));
  EXPECT_EQ(scene.obstacles[0].normal, (Vec3{0, 2, 0}));
  EXPECT_EQ(scene.obstacles[0].friction, 0.4);
  EXPECT_EQ(scene.obstacles[0].motion.kind, "translate");
  EXPECT_EQ(scene.obstacles[0].motion.velocity, (Vec3{0, 0.5, 0}));
  EXPECT_EQ(scene.obstacles[0].motion.until, 1.5);
  EXPECT_EQ(scene.obstacles[1].kind, "sphere");
  EXPECT_EQ(scene.obstacles[1].centre, (Vec3{1, 2, 3}));
  EXPECT_EQ(scene.obstacles[1].radius, 0.25);
  EXPECT_EQ(scene.obstacles[1].friction, 0.0);
  EXPECT_EQ(scene.obstacles[2].box_min, (Vec3{-1, -1, -1}));
  EXPECT_EQ(scene.obstacles[2].box_max, (Vec3{1, 0, 1}));
  // Without obstacles the contact defaults stand and nothing is added.
  const Scene plain = parse(kBoxScene);
  EXPECT_TRUE(plain.obstacles.empty());
  EXPECT_EQ(plain.contact.method, "energy");
  EXPECT_EQ(plain.contact.distance, 0.0);
}

TEST(Scene, ObstacleErrorsNameTheObstacleAndItsKey) {
  const std::string scene = std::string(kBoxScene) + "[[obstacle]]\n";
  expect_has(error_of(scene + "normal = [0, 0, 0]\n"),
             "scene.toml:4: obstacle.0.normal must not be [0, 0, 0]");
  expect_has(error_of(scene + "kind = \"cone\"\n"),
             "scene.toml:4: obstacle.0.kind must be one of \"plane\", \"sphere\", \"box\", got "
             "\"cone\"");
  expect_has(error_of(scene + "kind = \"sphere\"\n"), "obstacle.0.radius must be > 0, got 0");
  expect_has(error_of(scene + "kind = \"sphere\"\nradius = 1\nnormal = [1, 0, 0]\n"),
             "scene.toml:6: obstacle.0.normal belongs to an obstacle of obstacle.0.kind = "
             "\"plane\", but this one is \"sphere\"");
  expect_has(error_of(scene + "kind = \"box\"\nbox_min = [0, 0, 0]\nbox_max = [1, 0, 1]\n"),
             "obstacle.0.box_max must exceed obstacle.0.box_min along every axis");
  expect_has(error_of(scene + "friction = -0.1\n"), "obstacle.0.friction must be >= 0");
  expect_has(error_of(scene + "motion = { kind = \"spin\" }\n"),
             "obstacle.0.motion.kind must be one of");
  expect_has(error_of(scene + "radius = 1\n[[obstacle]]\nradis = 2\n"),
             "unknown key 'obstacle.1.radis' (did you mean 'obstacle.1.radius'?)");
}

TEST(Scene, ContactErrorsNameTheKey) {
  const std::string scene = std::string(kBoxScene) + "[[obstacle]]\n";
  expect_has(error_of(scene + "[contact]\nmethod = \"penalty\"\n"),
             "contact.method must be one of \"energy\", \"projection\"");
  expect_has(error_of(scene + "[contact]\ndistance = -1\n"), "contact.distance must be >= 0");
  expect_has(error_of(scene + "[contact]\nsmoothing_velocity = 0\n"),
             "contact.smoothing_velocity must be > 0");
  // The obstacles' barrier is evaluated by chebyshev, gd, jacobi_gd,
  // nesterov, ncg, lbfgs and newton (so far), the others with Jacobi's D,
  // newton with its CG solve.
  for (const char* method : {"gd", "jacobi_gd", "nesterov", "ncg", "lbfgs", "newton"})
    EXPECT_NO_THROW(parse(scene + "[solver]\nmethod = \"" + method + "\"\n")) << method;
  EXPECT_NO_THROW(parse(scene + "[solver]\npreconditioner = \"multilevel\"\n"));
  // newton refreshes the multilevel operator, obstacles' blocks in, at each
  // iterate.
  EXPECT_NO_THROW(
      parse(scene + "[solver]\nmethod = \"newton\"\npreconditioner = \"multilevel\"\n"));
  // linear_cg (corotated only) has no barrier yet.
  const std::vector<std::string> linear_cg = {"solver.method=\"linear_cg\"",
                                              "material.model=\"corotated\""};
  expect_has(error_of(scene, linear_cg),
             "obstacles ([[obstacle]]) with contact.method = \"energy\" (a barrier in eps) need "
             "solver.method = chebyshev, gd, jacobi_gd, nesterov, ncg, lbfgs or newton (got "
             "linear_cg)");
  expect_has(error_of(scene + "[solver]\nmethod = \"newton\"\nnewton_solver = \"ldlt\"\n"),
             "scene.toml:6: solver.newton_solver = \"ldlt\" assembles no contact terms, and "
             "obstacles ([[obstacle]]) with contact.method = \"energy\" put a barrier in eps; "
             "use \"cg\"");
  expect_has(error_of(scene + "[solver]\nmethod = \"lbfgs\"\npreconditioner = \"multilevel\"\n"),
             "solver.preconditioner = \"multilevel\" knows nothing of the contact barrier of "
             "obstacles ([[obstacle]]) with solver.method = lbfgs");
  EXPECT_NO_THROW(
      parse(scene + "[contact]\nmethod = \"projection\"\n[solver]\nmethod = \"lbfgs\"\n"));
  // An override is checked like a file entry.
  expect_has(error_of(scene, {"obstacle.0.friction=-1"}), "obstacle.0.friction must be >= 0");
}

// ------------------------------------------------------------------ bodies

constexpr const char* kTwoBodies = R"([[body]]
file = "meshes/ball.msh"
scale = 0.5
rotate = { axis = [1, 0, 0], degrees = 30 }
translate = [0, 1, 0]
velocity = [2, 0, 0]
angular_velocity = [0, 0, 3]
material = { young = 2e6, density = 500 }

[[body]]
[body.generator]
kind = "double_helix"
helix.preset = "41k"
)";

TEST(Scene, BodiesReadEveryKey) {
  const Scene scene = parse(kTwoBodies);
  ASSERT_EQ(scene.bodies.size(), 2u);
  const Body& ball = scene.bodies[0];
  EXPECT_EQ(ball.mesh.file, "meshes/ball.msh");
  EXPECT_EQ(ball.mesh.generator, "");
  EXPECT_EQ(ball.mesh.scale, 1.0);  // a body's scale is about its centroid
  EXPECT_EQ(ball.scale, 0.5);
  EXPECT_EQ(ball.rotate_axis, (Vec3{1, 0, 0}));
  EXPECT_EQ(ball.rotate_degrees, 30.0);
  EXPECT_EQ(ball.translate, (Vec3{0, 1, 0}));
  EXPECT_EQ(ball.velocity, (Vec3{2, 0, 0}));
  EXPECT_EQ(ball.angular_velocity, (Vec3{0, 0, 3}));
  EXPECT_EQ(ball.young, 2e6);
  EXPECT_EQ(ball.density, 500.0);
  EXPECT_EQ(parse("[[body]]\ngenerator = { kind = \"ball\", ball = { cells = 5, radius = 0.2, "
                  "centre = [1, 2, 3] } }\n")
                .bodies[0]
                .mesh.ball.radius,
            0.2);
  expect_has(error_of("[[body]]\ngenerator = { kind = \"ball\", ball = { radius = 0 } }\n"),
             "body.0.generator.ball.radius must be > 0, got 0");
  expect_has(error_of("[[body]]\ngenerator = { kind = \"box\", ball = { radius = 1 } }\n"),
             "body.0.generator.ball goes with body.0.generator.kind = \"ball\"");
  const CarParams car = parse(
                            "[[body]]\ngenerator = { kind = \"car\", car = { cells = 30, length "
                            "= 4, width = 2, height = 1.5, origin = [1, 2, 3] } }\n")
                            .bodies[0]
                            .mesh.car;
  EXPECT_EQ(car.cells, 30);
  EXPECT_EQ(car.length, 4.0);
  EXPECT_EQ(car.width, 2.0);
  EXPECT_EQ(car.height, 1.5);
  EXPECT_EQ(car.origin, (Vec3{1, 2, 3}));
  expect_has(error_of("[[body]]\ngenerator = { kind = \"car\", car = { cells = 4 } }\n"),
             "body.0.generator.car.cells must be in [8, 4000], got 4");
  expect_has(error_of("[mesh]\ngenerator = \"box\"\ncar = { width = 1 }\n"),
             "mesh.car goes with mesh.generator = \"car\", but mesh.generator is \"box\"");
  const Body& helix = scene.bodies[1];
  EXPECT_EQ(helix.mesh.generator, "double_helix");
  EXPECT_EQ(helix.mesh.helix.resolution, double_helix_preset_resolution("41k"));
  EXPECT_EQ(helix.young, 0.0);  // the scene's
  EXPECT_EQ(helix.scale, 1.0);
  // A scene of bodies has no [mesh].
  EXPECT_EQ(scene.mesh.generator, "");
  EXPECT_EQ(scene.mesh.file, "");
  // Overrides reach a body's keys like any other.
  EXPECT_EQ(parse(kTwoBodies, {"body.1.velocity=[0,-1,0]"}).bodies[1].velocity, (Vec3{0, -1, 0}));
}

TEST(Scene, BodyFilesAreRelativeToTheScene) {
  TempDir dir;
  const fs::path scene_file = dir.write("scene.toml", "[[body]]\nfile = \"ball.msh\"\n");
  EXPECT_EQ(load_scene(scene_file.string()).bodies[0].mesh.file,
            (dir.path() / "ball.msh").string());
}

TEST(Scene, BodyErrorsNameTheBodyAndItsKey) {
  const std::string box_body = "[[body]]\ngenerator = { kind = \"box\" }\n";
  expect_has(error_of(std::string(kBoxScene) + box_body), "[mesh] and [[body]] exclude each other");
  expect_has(error_of("[[body]]\nscale = 2\n"),
             "scene.toml:1: body.0 needs a mesh: set body.0.generator.kind (\"double_helix\", "
             "\"box\", \"ball\" or \"car\") or body.0.file");
  expect_has(error_of(box_body + "file = \"a.msh\"\n"),
             "body.0.file and body.0.generator.kind exclude each other");
  expect_has(error_of("[[body]]\ngenerator = { kind = \"cone\" }\n"),
             "body.0.generator.kind must be one of \"double_helix\", \"box\", \"ball\", \"car\", "
             "got \"cone\"");
  const std::string box_table = "[[body]]\n[body.generator]\nkind = \"box\"\n";
  expect_has(error_of(box_table + "helix.turns = 3\n"),
             "body.0.generator.helix goes with body.0.generator.kind = \"double_helix\", but "
             "body.0.generator.kind is \"box\"");
  expect_has(error_of("[[body]]\n[body.generator]\nkind = \"double_helix\"\nhelix.preset = "
                      "\"41k\"\nhelix.resolution = 2\n"),
             "scene.toml:5: body.0.generator.helix.resolution and body.0.generator.helix.preset "
             "exclude each other");
  expect_has(error_of(box_table + "box.cells = [0, 1, 1]\n"),
             "body.0.generator.box.cells must be at least 1 along each axis");
  expect_has(error_of(box_body + "scale = 0\n"), "scene.toml:3: body.0.scale must be > 0, got 0");
  expect_has(error_of(box_body + "rotate = { axis = [0, 0, 0], degrees = 10 }\n"),
             "body.0.rotate.axis must not be [0, 0, 0] when body.0.rotate.degrees is not 0");
  expect_has(error_of(box_body + "material = { young = -1 }\n"),
             "body.0.material.young must be > 0, got -1");
  expect_has(error_of(box_body + box_body + "material = { density = 0 }\n"),
             "scene.toml:5: body.1.material.density must be > 0, got 0");
  // The keys a body cannot override say where they belong.
  expect_has(error_of(box_body + "material = { poisson = 0.4 }\n"),
             "unknown key 'body.0.material.poisson' ('material.poisson' holds for the whole "
             "scene: set it in [material])");
  expect_has(error_of(box_body + "velocty = [1, 0, 0]\n"),
             "unknown key 'body.0.velocty' (did you mean 'body.0.velocity'?)");
  // A [mesh] key set from the command line replaces the bodies, and that
  // [mesh] then needs a mesh of its own.
  expect_has(error_of(box_body, {"mesh.scale=2"}), "--set mesh.scale=2: the scene needs a mesh");
}

TEST(Scene, ContactBetweenBodiesAsABarrierNeedsAMethodThatEvaluatesItWithJacobi) {
  const std::string two =
      "[[body]]\ngenerator = { kind = \"box\" }\n[[body]]\ngenerator = { kind "
      "= \"box\" }\ntranslate = [2, 0, 0]\n";
  EXPECT_NO_THROW(parse(two));
  EXPECT_TRUE(parse(kBoxScene, {"contact.self=true"}).contact.self);
  EXPECT_FALSE(parse(kBoxScene).contact.self);
  EXPECT_EQ(parse(two + "[contact]\nfriction = 0.3\n").contact.friction, 0.3);
  expect_has(error_of(two + "[contact]\nfriction = -0.3\n"),
             "contact.friction must be >= 0, got -0.3");
  EXPECT_NO_THROW(parse(two + "[solver]\nmethod = \"lbfgs\"\n"));
  EXPECT_NO_THROW(parse(two + "[solver]\nmethod = \"nesterov\"\n"));
  EXPECT_NO_THROW(parse(two + "[solver]\nmethod = \"newton\"\n"));
  // newton's multilevel CG takes the pairs' diagonal at each iterate.
  EXPECT_NO_THROW(parse(two + "[solver]\nmethod = \"newton\"\npreconditioner = \"multilevel\"\n"));
  EXPECT_NO_THROW(parse(two + "[solver]\nmethod = \"ncg\"\n"));
  const std::vector<std::string> linear_cg = {"solver.method=\"linear_cg\"",
                                              "material.model=\"corotated\""};
  expect_has(error_of(two, linear_cg),
             "a scene of several bodies ([[body]], contact between them) with "
             "contact.method = \"energy\" (a barrier in eps) need solver.method = chebyshev, gd, "
             "jacobi_gd, nesterov, ncg, lbfgs or newton (got linear_cg); contact.method = "
             "\"projection\" works with every method");
  expect_has(error_of(two + "[solver]\npreconditioner = \"multilevel\"\n"),
             "solver.preconditioner = \"multilevel\" knows nothing of the contact barrier of a "
             "scene of several bodies");
  expect_has(error_of(kBoxScene, {"contact.self=true", "solver.method=\"linear_cg\"",
                                  "material.model=\"corotated\""}),
             "contact.self = true (contact between bodies) with contact.method");
  // The projection pass runs after any method and preconditioner.
  const std::string projection = "[contact]\nmethod = \"projection\"\n";
  EXPECT_NO_THROW(parse(two + projection + "[solver]\nmethod = \"lbfgs\"\n"));
  EXPECT_NO_THROW(parse(two + projection + "[solver]\npreconditioner = \"multilevel\"\n"));
  EXPECT_NO_THROW(parse(kBoxScene + projection, {"contact.self=true", "solver.method=\"ncg\""}));
  // One body without self contact: any method, as before.
  EXPECT_NO_THROW(
      parse("[[body]]\ngenerator = { kind = \"box\" }\n[solver]\nmethod = \"lbfgs\"\n"));
}

}  // namespace
}  // namespace descent
