#pragma once
// Numbers as text for output files.
#include <charconv>
#include <string>

namespace descent {

// Shortest text that reads back as the same double.
inline std::string format_double(double value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::string(text, end);
}

}  // namespace descent
