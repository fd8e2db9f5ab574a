#pragma once
// Typo suggestions for messages ("did you mean 'run'?"): scene keys,
// command names.
#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace descent {

// Levenshtein distance: insertions, deletions and substitutions.
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> previous(b.size() + 1), current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

// The candidate close enough to be a typo of `name` (within two edits).
inline std::optional<std::string> closest_name(std::string_view name,
                                               const std::vector<std::string>& candidates) {
  constexpr std::size_t kFurthest = 2;
  std::optional<std::string> best;
  std::size_t best_distance = kFurthest + 1;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(name, candidate);
    if (distance < best_distance) {
      best = candidate;
      best_distance = distance;
    }
  }
  return best;
}

}  // namespace descent
