#pragma once
// Typed reading of scene values: each read_value converts a TOML node into
// the field it fills, or throws InputError
// "<where>: <key> must be <expected>, got <found>".
#include <array>
#include <string>
#include <vector>

#include "io/scene_document.hpp"
#include "io/scene_schema.hpp"

namespace descent {

// Integers only: 3.0 is not accepted as a count.
void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                int& field);
// Integers or floats, finite.
void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                double& field);
void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                std::string& field);
// true or false only: 1 and "yes" are not booleans.
void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                bool& field);
// Exactly 3 finite numbers.
void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                std::array<double, 3>& field);
// Exactly 3 integers.
void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                std::array<int, 3>& field);

// Any number of finite numbers / of integers (Chebyshev phases).
void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                std::vector<double>& field);
void read_value(const SceneDocument& doc, const toml::node& node, const std::string& key,
                std::vector<int>& field);

// Every key of the schema present in `doc`, read into its field; the rest
// keep their defaults. Expects the keys checked by reject_unknown_keys.
SceneFields read_scene_fields(const SceneDocument& doc);

}  // namespace descent
