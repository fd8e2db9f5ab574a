#include "contact/contact_islands.hpp"

#include <algorithm>

namespace descent {

std::vector<int> contact_islands(int num_bodies, const std::vector<std::pair<int, int>>& links,
                                 EnergyReduction& reduction) {
  // Labels travel negated through the maximum: its minimum over ranks.
  std::vector<double> label(static_cast<std::size_t>(num_bodies));
  for (int b = 0; b < num_bodies; ++b) label[b] = b;
  for (;;) {
    const std::vector<double> agreed = label;  // the same on every rank
    for (bool changed = true; changed;) {
      changed = false;
      for (const auto& [a, b] : links) {
        const double least = std::min(label[a], label[b]);
        if (label[a] != least || label[b] != least) {
          label[a] = label[b] = least;
          changed = true;
        }
      }
    }
    for (double& l : label) l = -l;
    reduction.max_in_place(label.data(), num_bodies);
    for (double& l : label) l = -l;
    // Unchanged on every rank's relaxation, or some rank lowered a label.
    if (label == agreed) break;
  }
  return std::vector<int>(label.begin(), label.end());
}

}  // namespace descent
