#pragma once
// Keys a scene may not set together, and how such a pair is settled when its
// keys come from two sources: a key of an override (--set, a study case)
// replaces the scene file's keys that exclude it, so a study of one key needs
// no copied scene. A pair that one source sets alone is left in place for the
// checks (scene_checks.hpp), which name both keys and where they were set.
#include <string>
#include <vector>

#include "io/scene_document.hpp"

namespace descent {

// Two keys (or tables) that exclude each other, as far as `applies` says:
// null means always; otherwise the pair conflicts only in documents where it
// returns true ("auto" excludes the fixed Chebyshev keys, "fixed" does not).
struct Exclusion {
  std::string first;
  std::string second;
  bool (*applies)(const SceneDocument& doc) = nullptr;
};

// Every pair that `doc` could hold, one per [[body]] for the keys of a body.
// The README's table of exclusions lists the same pairs.
std::vector<Exclusion> scene_exclusions(const SceneDocument& doc);

// Removes from `doc` each key that the scene file sets and that an override's
// key excludes. Runs once the overrides are merged and before any check.
void replace_excluded_keys(SceneDocument& doc);

}  // namespace descent
