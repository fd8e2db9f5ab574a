#pragma once
// The parsed scene TOML (the file with the --set overrides merged in) and
// what every stage of scene reading needs from it: finding a dotted key and
// saying where a node came from, for messages.
#include <toml++/toml.h>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace descent {

struct SceneDocument {
  toml::table root;
  std::string source;  // the scene file, or parse_scene's name for its text

  // The node at a dotted key ("solver.iterations", "fixed.0.axes": a number
  // indexes an array); null when absent.
  const toml::node* find(std::string_view key) const;
  toml::node* find(std::string_view key);
  bool has(std::string_view key) const { return find(key) != nullptr; }
  // Removes the entry at a dotted key whose parent is a table; false when
  // there is none.
  bool erase(std::string_view key);

  // False for nodes that came from a --set override.
  bool from_scene_file(const toml::node& node) const;
  // Whether an override (--set, a study case) set the node or anything
  // inside it: a table of the file that an override added a key to counts.
  bool set_by_override(const toml::node& node) const;

  // Where a node came from: "scene.toml:12" for the file, the override
  // ("--set solver.iterations=64") for an override.
  std::string where(const toml::node& node) const;
  // The same for a key; just the source for a key left at its default.
  std::string where(std::string_view key) const;
};

// "solver.iterations" -> {"solver", "iterations"}; segments may be empty.
std::vector<std::string_view> split_key(std::string_view key);

// A key segment naming an array entry ("0", "12"); nullopt for any other.
std::optional<std::size_t> parse_index(std::string_view segment);

// What a message says was found: `string "many"`, `integer 3`,
// `array [0, -9.81]`, `table`.
std::string describe(const toml::node& node);

// A number as a person writes it: 0.001, -9.81, 100000, inf.
std::string format_number(double value);

}  // namespace descent
