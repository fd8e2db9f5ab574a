#pragma once
// Command-line overrides of scene keys ("--set solver.iterations=64"),
// merged into the parsed file before any check so that an override is
// checked exactly like a file entry.
#include <toml++/toml.h>

#include <string>
#include <vector>

namespace descent {

// Applies each "dotted.key=value" to `root` in order, replacing or adding
// the entry and creating the tables on its way. The value is TOML
// ("gravity=[0,0,-9.81]", "mesh.file=\"a.msh\""); a bare word that is not
// TOML ("output.dir=runs/a") is taken as a string. A number segment indexes
// an array ("fixed.0.axes"); the index one past the end appends. The nodes an
// override adds carry "--set <override>" as their source, so messages about
// them name the override.
void apply_overrides(toml::table& root, const std::vector<std::string>& overrides);

}  // namespace descent
