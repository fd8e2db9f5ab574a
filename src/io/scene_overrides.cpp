#include "io/scene_overrides.hpp"

#include <optional>
#include <string_view>

#include "common/error.hpp"
#include "io/scene_document.hpp"

namespace descent {

namespace {

std::string_view trim(std::string_view text) {
  constexpr std::string_view kBlanks = " \t";
  const std::size_t first = text.find_first_not_of(kBlanks);
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(kBlanks) - first + 1);
}

std::string joined_key(const std::vector<std::string_view>& segments, std::size_t count) {
  std::string key;
  for (std::size_t i = 0; i < count; ++i) {
    if (i > 0) key += '.';
    key += segments[i];
  }
  return key;
}

// Text that failed to parse as TOML but does not open an array, an inline
// table or a string is meant as a plain string (a path, a name).
bool reads_as_bare_word(std::string_view text) {
  return std::string_view("[{\"'").find(text.front()) == std::string_view::npos;
}

std::string toml_quoted(std::string_view text) {
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

toml::table parse_value(std::string_view value_text, const std::string& label) {
  std::string document = "v = " + std::string(value_text);
  try {
    return toml::parse(document, std::string(label));
  } catch (const toml::parse_error& error) {
    if (!reads_as_bare_word(value_text)) {
      throw InputError(detail::concat(label, ": the value is not TOML (", error.description(),
                                      "); strings that are not one plain word need quotes"));
    }
  }
  document = "v = " + toml_quoted(value_text);
  try {
    return toml::parse(document, std::string(label));
  } catch (const toml::parse_error& error) {
    throw InputError(detail::concat(label, ": ", error.description()));
  }
}

// Walks one override's key through `root`, creating what is missing.
class OverridePath {
 public:
  OverridePath(std::vector<std::string_view> segments, std::string label)
      : segments_(std::move(segments)), label_(std::move(label)) {}

  void assign(toml::table& root, toml::node&& value) const {
    toml::node* container = &root;
    for (std::size_t i = 0; i + 1 < segments_.size(); ++i) {
      container = &child_for_descent(*container, i);
      if (!container->is_table() && !container->is_array()) {
        throw InputError(detail::concat(label_, ": ", joined_key(segments_, i + 1), " holds ",
                                        describe(*container), ", not a table"));
      }
    }
    const std::size_t last = segments_.size() - 1;
    if (toml::table* table = container->as_table()) {
      table->insert_or_assign(segments_[last], std::move(value));
      return;
    }
    toml::array& array = *container->as_array();
    const std::size_t index = array_index(array, last);
    if (index == array.size()) {
      array.push_back(std::move(value));
    } else {
      array.replace(array.cbegin() + static_cast<std::ptrdiff_t>(index), std::move(value));
    }
  }

 private:
  // The existing child at segment i of `container`, or a new one: an array
  // when the next segment is an index, else a table.
  toml::node& child_for_descent(toml::node& container, std::size_t i) const {
    const bool next_is_index = parse_index(segments_[i + 1]).has_value();
    if (toml::table* table = container.as_table()) {
      if (toml::node* existing = table->get(segments_[i])) return *existing;
      if (next_is_index) return table->insert(segments_[i], toml::array{}).first->second;
      return table->insert(segments_[i], toml::table{}).first->second;
    }
    toml::array& array = *container.as_array();
    const std::size_t index = array_index(array, i);
    if (index == array.size()) {
      if (next_is_index) {
        array.push_back(toml::array{});
      } else {
        array.push_back(toml::table{});
      }
    }
    return *array.get(index);
  }

  // Segment i read as an index into `array`: an entry, or one past the end.
  std::size_t array_index(const toml::array& array, std::size_t i) const {
    const std::string array_key = joined_key(segments_, i);
    const std::optional<std::size_t> index = parse_index(segments_[i]);
    if (!index) {
      throw InputError(detail::concat(label_, ": ", array_key,
                                      " is an array; name its entries by number, e.g. ", array_key,
                                      ".0"));
    }
    if (*index > array.size()) {
      throw InputError(detail::concat(label_, ": ", array_key, " has ", array.size(), " entries; ",
                                      array_key, ".", *index, " is past its end (", array_key, ".",
                                      array.size(), " appends one)"));
    }
    return *index;
  }

  std::vector<std::string_view> segments_;
  std::string label_;
};

void apply_override(toml::table& root, const std::string& text) {
  const std::string label = "--set " + text;
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos) {
    throw InputError(detail::concat(label, ": expected key=value, e.g. solver.iterations=64"));
  }
  const std::string_view key = trim(std::string_view(text).substr(0, equals));
  const std::string_view value_text = trim(std::string_view(text).substr(equals + 1));
  std::vector<std::string_view> segments = split_key(key);
  // Real keys are at most 4 deep (fixed.0.motion.kind); a deeper one is a
  // mistake, and a pathological one would exhaust the stack in toml++.
  constexpr std::size_t kMaxKeyDepth = 8;
  constexpr std::size_t kMaxValueLength = 4096;  // as a scene line: toml++ recursion
  if (value_text.size() > kMaxValueLength)
    throw InputError(detail::concat(label, ": the value has ", value_text.size(),
                                    " characters; at most ", kMaxValueLength));
  if (segments.size() > kMaxKeyDepth)
    throw InputError(detail::concat("--set ", key.substr(0, 64), key.size() > 64 ? "..." : "",
                                    ": a key has at most ", kMaxKeyDepth, " dotted parts"));
  for (std::string_view segment : segments) {
    if (segment.empty()) {
      throw InputError(detail::concat(label, ": '", key, "' is not a dotted key"));
    }
  }
  if (value_text.empty()) throw InputError(detail::concat(label, ": no value after '='"));

  toml::table parsed = parse_value(value_text, label);
  toml::node* value = parsed.get("v");
  if (parsed.size() != 1 || !value) {
    throw InputError(detail::concat(label, ": expected one value after '='"));
  }
  OverridePath(std::move(segments), label).assign(root, std::move(*value));
}

}  // namespace

void apply_overrides(toml::table& root, const std::vector<std::string>& overrides) {
  for (const std::string& text : overrides) apply_override(root, text);
}

}  // namespace descent
