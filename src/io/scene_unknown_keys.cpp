#include "io/scene_unknown_keys.hpp"

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "common/closest_name.hpp"
#include "common/error.hpp"
#include "io/scene_schema.hpp"

namespace descent {

namespace {

std::vector<std::string> scene_keys() {
  std::vector<std::string> keys;
  SceneFields unused;
  visit_scene_keys(unused, [&keys](std::string_view key, auto&) { keys.emplace_back(key); });
  return keys;
}

// An array of tables and the keys each of its tables may hold.
struct ArraySchema {
  std::string name;
  std::vector<std::string> entry_keys;
};

std::vector<ArraySchema> array_schemas() {
  std::vector<ArraySchema> arrays;
  Scene unused;
  visit_scene_arrays(unused, [&arrays](std::string_view name, auto& entries) {
    ArraySchema& array = arrays.emplace_back(ArraySchema{std::string(name), {}});
    visit_entry_keys(entries.emplace_back(),
                     [&array](std::string_view key, auto&) { array.entry_keys.emplace_back(key); });
  });
  return arrays;
}

std::string join_key(const std::string& table_key, std::string_view name) {
  return table_key.empty() ? std::string(name) : table_key + "." + std::string(name);
}

bool is_table_key(const std::vector<std::string>& keys, const std::string& key) {
  return std::any_of(keys.begin(), keys.end(),
                     [&key](const std::string& known) { return known.starts_with(key + "."); });
}

// The names that may appear directly in the table at `table_key`.
std::vector<std::string> names_in_table(const std::vector<std::string>& keys,
                                        const std::string& table_key) {
  const std::string prefix = table_key.empty() ? "" : table_key + ".";
  std::vector<std::string> names;
  for (const std::string& key : keys) {
    if (!key.starts_with(prefix)) continue;
    const std::string rest = key.substr(prefix.size());
    std::string name = rest.substr(0, rest.find('.'));
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

class KeyChecker {
 public:
  explicit KeyChecker(const SceneDocument& doc) : doc_(doc) {}

  void check_scene() const { check_table(doc_.root, scene_keys_, "", ""); }

 private:
  // `table` sits at `table_key` of the schema described by `keys`;
  // `shown_prefix` places that schema in the scene ("fixed.1." for the
  // second [[fixed]] table, empty outside the arrays of tables).
  void check_table(const toml::table& table, const std::vector<std::string>& keys,
                   const std::string& table_key, const std::string& shown_prefix) const {
    const bool at_scene_root = table_key.empty() && shown_prefix.empty();
    for (auto&& [name, node] : table) {
      const std::string key = join_key(table_key, name.str());
      // A quoted name with a dot ("solver.rho" = 1) would pass for a nested key.
      const bool plain_name = name.str().find('.') == std::string_view::npos;
      if (plain_name && std::find(keys.begin(), keys.end(), key) != keys.end()) continue;
      if (plain_name && is_table_key(keys, key)) {
        if (!node.is_table()) throw_wrong_kind(node, shown_prefix + key, "a table");
        check_table(*node.as_table(), keys, key, shown_prefix);
        continue;
      }
      if (const ArraySchema* array = at_scene_root ? find_array(name.str()) : nullptr) {
        check_array_entries(node, *array);
        continue;
      }
      throw_unknown(node, name.str(), keys, table_key, shown_prefix);
    }
  }

  const ArraySchema* find_array(std::string_view name) const {
    for (const ArraySchema& array : arrays_) {
      if (array.name == name) return &array;
    }
    return nullptr;
  }

  void check_array_entries(const toml::node& node, const ArraySchema& array) const {
    const toml::array* entries = node.as_array();
    if (!entries) {
      throw_wrong_kind(node, array.name,
                       detail::concat("an array of tables ([[", array.name, "]])"));
    }
    for (std::size_t i = 0; i < entries->size(); ++i) {
      const std::string entry_key = detail::concat(array.name, ".", i);
      const toml::node& entry = *entries->get(i);
      if (!entry.is_table()) throw_wrong_kind(entry, entry_key, "a table");
      check_table(*entry.as_table(), array.entry_keys, "", entry_key + ".");
    }
  }

  [[noreturn]] void throw_wrong_kind(const toml::node& node, const std::string& shown_key,
                                     std::string_view expected) const {
    throw InputError(detail::concat(doc_.where(node), ": ", shown_key, " must be ", expected,
                                    ", got ", describe(node)));
  }

  bool is_top_level_name(std::string_view name) const {
    const std::vector<std::string> names = names_in_table(scene_keys_, "");
    return find_array(name) || std::find(names.begin(), names.end(), name) != names.end();
  }

  // Names the key with the full dotted path and, when there is one, a close
  // key of the same table. Failing that, explains TOML's classic trap: a
  // top-level key written below a [table] header belongs to that table.
  [[noreturn]] void throw_unknown(const toml::node& node, std::string_view name,
                                  const std::vector<std::string>& keys,
                                  const std::string& table_key,
                                  const std::string& shown_prefix) const {
    const bool at_scene_root = table_key.empty() && shown_prefix.empty();
    std::string message = detail::concat(doc_.where(node), ": unknown key '", shown_prefix,
                                         join_key(table_key, name), "'");
    std::vector<std::string> candidates = names_in_table(keys, table_key);
    if (at_scene_root) {
      for (const ArraySchema& array : arrays_) candidates.push_back(array.name);
    }
    const std::string scene_key = join_key(table_key, name);
    if (const std::optional<std::string> close = closest_name(name, candidates)) {
      message += " (did you mean '" + shown_prefix + join_key(table_key, *close) + "'?)";
    } else if (!shown_prefix.empty() && !table_key.empty() &&
               std::find(scene_keys_.begin(), scene_keys_.end(), scene_key) != scene_keys_.end()) {
      // [body.material] takes some of [material]'s keys; the others hold for
      // the whole scene.
      message += detail::concat(" ('", scene_key, "' holds for the whole scene: set it in [",
                                table_key, "])");
    } else if (!at_scene_root && is_top_level_name(name)) {
      message +=
          detail::concat(" ('", name, "' is a top-level key: write it above the first [table])");
    }
    throw InputError(message);
  }

  const SceneDocument& doc_;
  const std::vector<std::string> scene_keys_ = scene_keys();
  const std::vector<ArraySchema> arrays_ = array_schemas();
};

}  // namespace

void reject_unknown_keys(const SceneDocument& doc) { KeyChecker(doc).check_scene(); }

}  // namespace descent
