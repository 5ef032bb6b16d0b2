// Checked scalar reads for the scenario parser (see yaml_read.hpp).
#include "yaml_read.hpp"

#include <rapidjson/stringbuffer.h>
#include <rapidjson/writer.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "did_you_mean.hpp"
#include "ocp/bounded_file.hpp"

namespace ocp::scenario {

ScenarioError::ScenarioError(std::string file, int line, int column, std::string reason)
    : std::runtime_error(file + ":" + std::to_string(line) + ":" + std::to_string(column) +
                         ": " + reason),
      file_(std::move(file)), line_(line), column_(column), reason_(std::move(reason)) {}

ScenarioError::ScenarioError(std::string file, std::string message)
    : std::runtime_error(message), file_(std::move(file)), line_(0), column_(0), reason_(std::move(message)) {}

Mark YamlReader::mark(const YAML::Node& node) const {
  const YAML::Mark m = node.Mark();
  if (m.is_null()) return Mark{1, 1};
  return Mark{m.line + 1, m.column + 1};
}

void YamlReader::fail(const YAML::Node& node, const std::string& reason) const {
  const Mark m = mark(node);
  throw ScenarioError(file_, m.line, m.column, reason);
}

void YamlReader::check_keys(const YAML::Node& node, std::string_view what,
                            std::initializer_list<std::string_view> allowed) const {
  if (!node.IsMap()) fail(node, std::string(what) + ": expected a mapping");
  for (const auto& item : node) {
    const std::string key = item.first.as<std::string>();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    fail(item.first, unknown_name("key", key, std::vector<std::string>(allowed.begin(), allowed.end()), what));
  }
}

void YamlReader::fail_unknown(const YAML::Node& node, std::string_view what, const std::string& word,
                              const std::vector<std::string>& known) const {
  fail(node, unknown_name(what, word, known));
}

YAML::Node YamlReader::require(const YAML::Node& map, const char* key, std::string_view what) const {
  YAML::Node value = map[key];
  if (!value) fail(map, std::string(what) + ": missing required key '" + key + "'");
  return value;
}

std::string YamlReader::text(const YAML::Node& node) const {
  if (!node.IsScalar()) fail(node, "expected a string");
  return node.Scalar();
}

bool YamlReader::boolean(const YAML::Node& node) const {
  const std::string value = node.IsScalar() ? node.Scalar() : "";
  if (value == "true") return true;
  if (value == "false") return false;
  fail(node, "expected true or false, got '" + escaped_excerpt(value) + "'");
}

double YamlReader::number(const YAML::Node& node, double min, double max) const {
  const std::string value = node.IsScalar() ? node.Scalar() : "";
  char* end = nullptr;
  errno = 0;
  const double parsed = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || errno != 0 || !std::isfinite(parsed)) {
    fail(node, "expected a number, got '" + escaped_excerpt(value) + "'");
  }
  if (parsed < min || parsed > max) {
    fail(node, "value " + value + " out of range [" + std::to_string(min) + ", " +
                   std::to_string(max) + "]");
  }
  return parsed;
}

std::uint64_t YamlReader::integer(const YAML::Node& node) const {
  const std::string value = node.IsScalar() ? node.Scalar() : "";
  char* end = nullptr;
  errno = 0;
  const unsigned long long parsed = std::strtoull(value.c_str(), &end, 10);
  if (value.empty() || value[0] == '-' || *end != '\0' || errno != 0) {
    fail(node, "expected a non-negative integer, got '" + escaped_excerpt(value) + "'");
  }
  return parsed;
}

Micros parse_duration_text(const std::string& text) {
  std::size_t split = 0;
  while (split < text.size() && (std::isdigit(static_cast<unsigned char>(text[split])) ||
                                 text[split] == '.')) {
    ++split;
  }
  const std::string digits = text.substr(0, split);
  const std::string unit = text.substr(split);
  if (digits.empty()) {
    throw std::invalid_argument("expected a duration like 350ms or 12.5s, got '" + escaped_excerpt(text) + "'");
  }
  if (!unit.empty() && (unit[0] == 'e' || unit[0] == 'E')) {
    throw std::invalid_argument("duration '" + escaped_excerpt(text) +
                                "': write it without an exponent, as a number and a unit (us, ms, s, min or h)");
  }
  char* end = nullptr;
  const double value = std::strtod(digits.c_str(), &end);
  if (*end != '\0') throw std::invalid_argument("bad number in duration '" + text + "'");
  double scale = 0;
  if (unit == "us") scale = 1;
  else if (unit == "ms") scale = 1e3;
  else if (unit == "s") scale = 1e6;
  else if (unit == "min") scale = 60e6;
  else if (unit == "h") scale = 3600e6;
  else if (unit.empty() && value == 0) scale = 0;
  else throw std::invalid_argument("duration '" + escaped_excerpt(text) + "' needs a unit: us, ms, s, min or h");
  // Beyond 2^62 us (about 146 000 years) the sums of times (a deadline plus a delay) would
  // overflow 64 bits; 2^62 us itself is the largest, and acts as "never".
  if (!(value * scale <= static_cast<double>(max_duration_us))) {
    throw std::invalid_argument("duration '" + escaped_excerpt(text) + "' is beyond the largest, " +
                                std::to_string(max_duration_us) + "us (2^62 us, about 146 000 years)");
  }
  return Micros{static_cast<std::int64_t>(std::llround(value * scale))};
}

namespace {
ParseLimits current_limits;
}  // namespace

const ParseLimits& parse_limits() { return current_limits; }
void set_parse_limits(const ParseLimits& limits) { current_limits = limits; }

Micros YamlReader::duration(const YAML::Node& node) const {
  if (!node.IsScalar()) fail(node, "expected a duration like 350ms or 12.5s");
  try {
    return parse_duration_text(node.Scalar());
  } catch (const std::invalid_argument& error) {
    fail(node, error.what());
  }
}

namespace {
using JsonWriter = rapidjson::Writer<rapidjson::StringBuffer>;

// JSON's number grammar (RFC 8259 §6): such a scalar is copied as its own text, so a u64 above
// 2^63 or a long fraction reaches the vehicle digit for digit, as the product passes it on.
bool json_number_text(std::string_view text) {
  std::size_t i = 0;
  const auto digits = [&] {
    const std::size_t start = i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
    return i > start;
  };
  if (i < text.size() && text[i] == '-') ++i;
  if (i < text.size() && text[i] == '0') ++i;
  else if (!digits()) return false;
  if (i < text.size() && text[i] == '.') {
    ++i;
    if (!digits()) return false;
  }
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    if (!digits()) return false;
  }
  return i == text.size();
}

// yaml-cpp shares an alias's node instead of copying it, so a file of a few lines can stand for
// billions of nodes ("billion laughs"): they are counted as they are written, and refused past
// the limit before they cost memory.
void write_json(const YAML::Node& node, JsonWriter& json, std::size_t& nodes_left) {
  if (nodes_left == 0) throw std::length_error("expanded node count");
  --nodes_left;
  switch (node.Type()) {
    case YAML::NodeType::Map:
      json.StartObject();
      for (const auto& item : node) {
        const std::string key = item.first.as<std::string>();
        json.Key(key.c_str(), static_cast<rapidjson::SizeType>(key.size()));
        write_json(item.second, json, nodes_left);
      }
      json.EndObject();
      return;
    case YAML::NodeType::Sequence:
      json.StartArray();
      for (const auto& item : node) write_json(item, json, nodes_left);
      json.EndArray();
      return;
    case YAML::NodeType::Scalar: {
      const std::string& value = node.Scalar();
      // A quoted scalar ("42") stays a string; plain ones are typed as YAML 1.2 core would.
      if (node.Tag() != "!") {
        if (value == "true" || value == "false") { json.Bool(value == "true"); return; }
        if (value == "null" || value == "~") { json.Null(); return; }
        if (json_number_text(value)) {
          json.RawValue(value.c_str(), value.size(), rapidjson::kNumberType);
          return;
        }
        char* end = nullptr;
        const long long whole = std::strtoll(value.c_str(), &end, 10);
        if (!value.empty() && *end == '\0') { json.Int64(whole); return; }
        const double real = std::strtod(value.c_str(), &end);
        if (!value.empty() && *end == '\0' && std::isfinite(real)) { json.Double(real); return; }
      }
      json.String(value.c_str(), static_cast<rapidjson::SizeType>(value.size()));
      return;
    }
    default:
      json.Null();
  }
}
}  // namespace

std::string YamlReader::json(const YAML::Node& node) const {
  rapidjson::StringBuffer buffer;
  JsonWriter json(buffer);
  std::size_t nodes_left = parse_limits().max_value_nodes;
  try {
    write_json(node, json, nodes_left);
  } catch (const std::length_error&) {
    fail(node, "this value expands to more than " + std::to_string(parse_limits().max_value_nodes) +
                   " nodes (YAML aliases are expanded); make it smaller");
  }
  return std::string(buffer.GetString(), buffer.GetSize());
}

}  // namespace ocp::scenario
