#pragma once
// Whole-number options (--threads, --parts, --frames ...) refused in words:
// "--parts: must be a whole number of at least 1, not '0'". CLI11's
// PositiveNumber would print its range up to the largest double.
#include <CLI/CLI.hpp>
#include <exception>
#include <string>

namespace descent {

inline CLI::Validator at_least(long minimum) {
  return CLI::Validator(
      [minimum](std::string& text) -> std::string {
        std::size_t used = 0;
        long value = 0;
        try {
          value = std::stol(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used == text.size() && value >= minimum) return "";
        return "must be a whole number of at least " + std::to_string(minimum) + ", not '" + text +
               "'";
      },
      "N>=" + std::to_string(minimum));
}

}  // namespace descent
