#include "io/scene_values.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "common/error.hpp"

namespace descent {

namespace {

[[noreturn]] void throw_wrong_value(const SceneDocument& doc, const toml::node& node,
                                    const std::string& key, std::string_view expected) {
  throw InputError(
      detail::concat(doc.where(node), ": ", key, " must be ", expected, ", got ", describe(node)));
}

// Integers count as numbers wherever a float is expected.
std::optional<double> number_of(const toml::node& node) {
  if (const auto* integer = node.as_integer()) return static_cast<double>(integer->get());
  if (const auto* floating = node.as_floating_point()) return floating->get();
  return std::nullopt;
}

std::optional<int> int_of(const toml::node& node) {
  const auto* integer = node.as_integer();
  if (!integer) return std::nullopt;
  const std::int64_t value = integer->get();
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
    return std::nullopt;
  return static_cast<int>(value);
}

}  // namespace

void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                int& field) {
  const std::optional<int> value = int_of(node);
  if (!value) {
    throw_wrong_value(doc, node, key,
                      node.is_integer() ? "an integer that fits in 32 bits" : "an integer");
  }
  field = *value;
}

void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                double& field) {
  const std::optional<double> value = number_of(node);
  if (!value) throw_wrong_value(doc, node, key, "a number");
  if (!std::isfinite(*value)) throw_wrong_value(doc, node, key, "a finite number");
  field = *value;
}

void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                std::string& field) {
  const auto* text = node.as_string();
  if (!text) throw_wrong_value(doc, node, key, "a string");
  field = text->get();
}

void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                bool& field) {
  const auto* flag = node.as_boolean();
  if (!flag) throw_wrong_value(doc, node, key, "a boolean (true or false)");
  field = flag->get();
}

void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                std::array<double, 3>& field) {
  const toml::array* array = node.as_array();
  if (!array || array->size() != 3) throw_wrong_value(doc, node, key, "an array of 3 numbers");
  for (std::size_t i = 0; i < 3; ++i) {
    const std::optional<double> value = number_of(*array->get(i));
    if (!value) throw_wrong_value(doc, node, key, "an array of 3 numbers");
    if (!std::isfinite(*value)) throw_wrong_value(doc, node, key, "an array of 3 finite numbers");
    field[i] = *value;
  }
}

void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                std::array<int, 3>& field) {
  const toml::array* array = node.as_array();
  if (!array || array->size() != 3) throw_wrong_value(doc, node, key, "an array of 3 integers");
  for (std::size_t i = 0; i < 3; ++i) {
    const std::optional<int> value = int_of(*array->get(i));
    if (!value) throw_wrong_value(doc, node, key, "an array of 3 integers");
    field[i] = *value;
  }
}

void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                std::vector<double>& field) {
  const toml::array* array = node.as_array();
  if (!array) throw_wrong_value(doc, node, key, "an array of numbers");
  field.clear();
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::optional<double> value = number_of(*array->get(i));
    if (!value || !std::isfinite(*value))
      throw_wrong_value(doc, node, key, "an array of finite numbers");
    field.push_back(*value);
  }
}

void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                std::vector<int>& field) {
  const toml::array* array = node.as_array();
  if (!array) throw_wrong_value(doc, node, key, "an array of integers");
  field.clear();
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::optional<int> value = int_of(*array->get(i));
    if (!value) throw_wrong_value(doc, node, key, "an array of integers");
    field.push_back(*value);
  }
}

SceneFields read_scene_fields(const SceneDocument& doc) {
  SceneFields fields;
  visit_scene_keys(fields, [&doc](std::string_view key, auto& field) {
    if (const toml::node* node = doc.find(key)) read_value(doc, *node, std::string(key), field);
  });

  // One entry per table of the array, each starting from the struct defaults.
  visit_scene_arrays(fields.scene, [&doc](std::string_view name, auto& entries) {
    const toml::array* tables = doc.root.get_as<toml::array>(name);
    for (std::size_t i = 0; tables && i < tables->size(); ++i) {
      const std::string prefix = detail::concat(name, ".", i, ".");
      visit_entry_keys(entries.emplace_back(), [&](std::string_view key, auto& field) {
        const std::string full_key = prefix + std::string(key);
        if (const toml::node* node = doc.find(full_key)) read_value(doc, *node, full_key, field);
      });
    }
  });
  return fields;
}

}  // namespace descent
