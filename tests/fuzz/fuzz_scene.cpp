// Fuzz target for descent::parse_scene. Bad scenes must end in
// descent::Error; any other exception, a crash, a sanitizer report or an
// accepted scene that breaks the documented rules is a finding.
//
// Input: TOML text. Lines that start with "--set " are taken out of it and
// passed, in order, as command-line overrides ("--set solver.iterations=64"),
// so the fuzzer reaches the override merging as well as the file parser.
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "common/error.hpp"
#include "io/scene.hpp"
#include "tests/fuzz/fuzz_common.hpp"

namespace {

constexpr std::string_view kSetPrefix = "--set ";

// Checks a few of the rules parse_scene promises to enforce; an accepted
// scene that breaks one slipped past a check.
void check_scene(const descent::Scene& scene) {
  using descent::fuzz::broken_promise;
  if (scene.bodies.empty() && scene.mesh.generator.empty() == scene.mesh.file.empty())
    broken_promise("the scene has both or neither of mesh.generator and mesh.file");
  for (const descent::Body& body : scene.bodies) {
    if (body.mesh.generator.empty() == body.mesh.file.empty())
      broken_promise("a body has both or neither of generator.kind and file");
    if (!(body.scale > 0) || body.young < 0 || body.density < 0)
      broken_promise("a body's scale or material is out of range");
  }
  if (!scene.bodies.empty() && !(scene.mesh.generator.empty() && scene.mesh.file.empty()))
    broken_promise("a scene has both [mesh] and [[body]]");
  if (!(scene.mesh.scale > 0)) broken_promise("mesh.scale is not > 0");
  if (!(scene.time.dt > 0) || !std::isfinite(scene.time.dt)) broken_promise("time.dt is bad");
  if (scene.time.frames < 0 || scene.solver.iterations < 1) broken_promise("a count is bad");
  if (!(scene.material.young > 0) || !(scene.material.poisson > -1) ||
      !(scene.material.poisson < 0.5))
    broken_promise("the material is out of range");
  for (const descent::FixedRegion& region : scene.fixed) {
    if (region.axes.empty() || region.axes.size() > 3) broken_promise("fixed axes are bad");
    for (int axis = 0; axis < 3; ++axis)
      if (!(region.box_min[axis] <= region.box_max[axis]))
        broken_promise("a fixed box is inverted");
  }
  for (const descent::LoadRegion& load : scene.loads)
    if (!(load.ramp >= 0)) broken_promise("a load ramp is negative");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  std::string toml_text;
  std::vector<std::string> overrides;
  for (std::size_t begin = 0; begin < input.size();) {
    const std::size_t newline = input.find('\n', begin);
    const std::size_t end = newline == std::string_view::npos ? input.size() : newline + 1;
    const std::string_view line = input.substr(begin, end - begin);
    if (line.starts_with(kSetPrefix)) {
      std::string_view value = line.substr(kSetPrefix.size());
      if (value.ends_with('\n')) value.remove_suffix(1);
      overrides.emplace_back(value);
    } else {
      toml_text += line;
    }
    begin = end;
  }

  try {
    check_scene(descent::parse_scene(toml_text, "fuzz.toml", overrides));
    ++descent::fuzz::accepted_inputs;
  } catch (const descent::Error&) {
    // Expected: bad input is reported, not crashed on.
  }
  return 0;
}
