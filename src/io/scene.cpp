#include "io/scene.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>

#include "common/error.hpp"
#include "io/scene_checks.hpp"
#include "io/scene_document.hpp"
#include "io/scene_exclusions.hpp"
#include "io/scene_overrides.hpp"
#include "io/scene_unknown_keys.hpp"
#include "io/scene_values.hpp"

namespace descent {

namespace {

// toml++ recurses once per dotted-key part and per nesting level; a line
// long enough to hold tens of thousands of them overflows the stack. No
// scene needs a line near this long.
constexpr std::size_t kMaxLineLength = 4096;

void reject_overlong_lines(std::string_view text, const std::string& source) {
  std::size_t line = 1, start = 0;
  for (std::size_t end = 0; end <= text.size(); ++end) {
    if (end < text.size() && text[end] != '\n') continue;
    if (end - start > kMaxLineLength)
      throw InputError(detail::concat(source, ":", line, ": line of ", end - start,
                                      " characters; a scene line has at most ", kMaxLineLength));
    ++line;
    start = end + 1;
  }
}

SceneDocument parse_document(std::string_view text, const std::string& source) {
  reject_overlong_lines(text, source);
  try {
    return SceneDocument{toml::parse(text, std::string(source)), source};
  } catch (const toml::parse_error& error) {
    const toml::source_position& at = error.source().begin;
    throw InputError(
        detail::concat(source, ":", at.line, ":", at.column, ": ", error.description()));
  }
}

// A relative mesh.file (or body file) written in a scene file means "next to the scene", so
// a scene runs from any directory; one given with --set is relative to where
// the user typed it, like any other path on a command line.
// `key` is where the scene sets it: "mesh.file", "body.2.file".
void resolve_mesh_file(const SceneDocument& doc, const std::filesystem::path& scene_dir,
                       const std::string& key, MeshSpec& mesh) {
  const toml::node* file = doc.find(key);
  if (!file || !doc.from_scene_file(*file)) return;
  const std::filesystem::path path(mesh.file);
  if (path.is_relative()) mesh.file = (scene_dir / path).lexically_normal().string();
}

// Overrides first, so each stage below treats them exactly as file entries,
// and with them gone the file's keys that they exclude.
Scene read_scene(SceneDocument doc, const std::vector<std::string>& overrides,
                 const std::filesystem::path& scene_dir) {
  apply_overrides(doc.root, overrides);
  replace_excluded_keys(doc);
  reject_unknown_keys(doc);
  SceneFields fields = read_scene_fields(doc);
  check_mesh_source(doc, fields.scene);
  apply_helix_preset(doc, fields);
  resolve_chebyshev_parameters(doc, fields.scene.solver);
  resolve_step_accuracy(doc, fields.scene.solver);
  check_scene_values(doc, fields.scene);
  resolve_mesh_file(doc, scene_dir, "mesh.file", fields.scene.mesh);
  std::vector<Body>& bodies = fields.scene.bodies;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    resolve_mesh_file(doc, scene_dir, detail::concat("body.", i, ".file"), bodies[i].mesh);
  fields.scene.source = doc.source;
  return std::move(fields.scene);
}

}  // namespace

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  if (!std::filesystem::exists(path)) {
    throw InputError(detail::concat("scene file '", path, "' does not exist"));
  }
  if (std::filesystem::is_directory(path)) {
    throw InputError(detail::concat("scene file '", path, "' is a directory"));
  }
  std::ifstream file(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  if (!file.is_open() || file.bad()) {
    throw InputError(detail::concat("scene file '", path, "' cannot be read"));
  }
  return read_scene(parse_document(text, path), overrides,
                    std::filesystem::path(path).parent_path());
}

Scene parse_scene(const std::string& toml_text, const std::string& source,
                  const std::vector<std::string>& overrides) {
  // Messages start with the source, so it needs a name.
  const std::string name = source.empty() ? std::string("<scene text>") : source;
  // Without a file, relative paths stay relative to the current directory.
  return read_scene(parse_document(toml_text, name), overrides, {});
}

}  // namespace descent
