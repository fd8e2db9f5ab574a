#include "io/scene_document.hpp"

#include <charconv>
#include <iomanip>
#include <sstream>

namespace descent {

namespace {

// Tables that --set creates on the way to its value have no source of their
// own; they are located by the first node inside them that has one.
const toml::source_region* located_region(const toml::node& node) {
  if (node.source().path) return &node.source();
  if (const toml::table* table = node.as_table()) {
    for (auto&& [key, child] : *table) {
      if (const toml::source_region* region = located_region(child)) return region;
    }
  }
  if (const toml::array* array = node.as_array()) {
    for (const toml::node& child : *array) {
      if (const toml::source_region* region = located_region(child)) return region;
    }
  }
  return nullptr;
}

// TOML's own names for its types.
std::string_view type_name(toml::node_type type) {
  switch (type) {
    case toml::node_type::string:
      return "string";
    case toml::node_type::integer:
      return "integer";
    case toml::node_type::floating_point:
      return "float";
    case toml::node_type::boolean:
      return "boolean";
    case toml::node_type::date:
      return "date";
    case toml::node_type::time:
      return "time";
    case toml::node_type::date_time:
      return "date-time";
    case toml::node_type::array:
      return "array";
    case toml::node_type::table:
      return "table";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

std::string value_text(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "\"" + node.as_string()->get() + "\"";
    case toml::node_type::integer:
      return std::to_string(node.as_integer()->get());
    case toml::node_type::floating_point:
      return format_number(node.as_floating_point()->get());
    case toml::node_type::boolean:
      return node.as_boolean()->get() ? "true" : "false";
    case toml::node_type::array: {
      std::string text = "[";
      for (const toml::node& element : *node.as_array()) {
        if (text.size() > 1) text += ", ";
        text += value_text(element);
      }
      return text + "]";
    }
    case toml::node_type::table:
      return "{...}";
    default: {  // dates and times: toml++ prints them as TOML does
      std::ostringstream os;
      node.visit([&os](const auto& value) { os << value; });
      return os.str();
    }
  }
}

}  // namespace

const toml::node* SceneDocument::find(std::string_view key) const {
  const toml::node* node = &root;
  for (std::string_view segment : split_key(key)) {
    if (const toml::table* table = node->as_table()) {
      node = table->get(segment);
    } else if (const toml::array* array = node->as_array()) {
      const std::optional<std::size_t> index = parse_index(segment);
      node = index ? array->get(*index) : nullptr;
    } else {
      node = nullptr;
    }
    if (!node) return nullptr;
  }
  return node;
}

toml::node* SceneDocument::find(std::string_view key) {
  return const_cast<toml::node*>(static_cast<const SceneDocument&>(*this).find(key));
}

bool SceneDocument::erase(std::string_view key) {
  const std::size_t dot = key.rfind('.');
  toml::node* parent = dot == std::string_view::npos ? &root : find(key.substr(0, dot));
  toml::table* table = parent ? parent->as_table() : nullptr;
  const std::string_view name = dot == std::string_view::npos ? key : key.substr(dot + 1);
  return table && table->erase(name) > 0;
}

bool SceneDocument::set_by_override(const toml::node& node) const {
  if (node.source().path && *node.source().path != source) return true;
  if (const toml::table* table = node.as_table()) {
    for (auto&& [key, child] : *table)
      if (set_by_override(child)) return true;
  }
  if (const toml::array* array = node.as_array()) {
    for (const toml::node& child : *array)
      if (set_by_override(child)) return true;
  }
  return false;
}

bool SceneDocument::from_scene_file(const toml::node& node) const {
  const toml::source_region* region = located_region(node);
  return region && *region->path == source;
}

std::string SceneDocument::where(const toml::node& node) const {
  const toml::source_region* region = located_region(node);
  if (!region) return source;
  // An override's nodes carry the override itself as their source path.
  if (*region->path != source) return *region->path;
  return source + ":" + std::to_string(region->begin.line);
}

std::string SceneDocument::where(std::string_view key) const {
  const toml::node* node = find(key);
  return node ? where(*node) : source;
}

std::vector<std::string_view> split_key(std::string_view key) {
  std::vector<std::string_view> segments;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    segments.push_back(key.substr(start, dot - start));
    if (dot == std::string_view::npos) return segments;
    start = dot + 1;
  }
}

std::optional<std::size_t> parse_index(std::string_view segment) {
  std::size_t index = 0;
  const char* end = segment.data() + segment.size();
  const auto [stop, error] = std::from_chars(segment.data(), end, index);
  if (segment.empty() || error != std::errc{} || stop != end) return std::nullopt;
  return index;
}

std::string describe(const toml::node& node) {
  if (node.is_table()) return "table";
  constexpr std::size_t kLongest = 60;  // a message quotes a value, not a document
  std::string text = value_text(node);
  if (text.size() > kLongest) text = text.substr(0, kLongest - 3) + "...";
  return std::string(type_name(node.type())) + " " + text;
}

std::string format_number(double value) {
  std::ostringstream os;
  os << std::setprecision(15) << value;
  return os.str();
}

}  // namespace descent
