#pragma once
// Rejects keys the scene schema does not know, naming the full dotted key,
// where it was written and, when one is close, the key that was meant.
#include "io/scene_document.hpp"

namespace descent {

// Throws InputError for the first unknown key, or for a key that must hold
// a table ([solver], [[fixed]]) but holds something else.
void reject_unknown_keys(const SceneDocument& doc);

}  // namespace descent
