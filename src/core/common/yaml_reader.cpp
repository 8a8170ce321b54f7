#include "room_reverb/common/yaml_reader.h"

#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

void YamlReader::fail(const YAML::Node& node, const std::string& key, const std::string& message) const {
  std::string where = source_;
  if (node.IsDefined() && node.Mark().line >= 0) where += ":" + std::to_string(node.Mark().line + 1);
  throw InputError(where + ": " + key + ": " + message);
}

YAML::Node YamlReader::require(const YAML::Node& parent, const std::string& name, const std::string& key,
                               const std::string& why) const {
  const YAML::Node node = parent[name];
  if (!node.IsDefined() || node.IsNull()) fail(parent, key, why);
  return node;
}

void YamlReader::requireMap(const YAML::Node& node, const std::string& key) const {
  if (!node.IsMap()) fail(node, key, "must be a map of keys to values");
}

std::string YamlReader::text(const YAML::Node& node, const std::string& key) const {
  if (!node.IsScalar() || node.Scalar().empty()) fail(node, key, "must be a non-empty name");
  return node.Scalar();
}

std::string YamlReader::textOr(const YAML::Node& parent, const std::string& name, const std::string& key,
                               const std::string& fallback) const {
  const YAML::Node node = parent[name];
  return node.IsDefined() && !node.IsNull() ? text(node, key) : fallback;
}

double YamlReader::number(const YAML::Node& node, const std::string& key) const {
  if (!node.IsScalar()) fail(node, key, "must be a number");
  double value = 0.0;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    fail(node, key, "'" + node.Scalar() + "' is not a number");
  }
  if (!std::isfinite(value)) fail(node, key, "must be finite (got " + node.Scalar() + ")");
  return value;
}

double YamlReader::numberOr(const YAML::Node& parent, const std::string& name, const std::string& key,
                            double fallback) const {
  const YAML::Node node = parent[name];
  return node.IsDefined() && !node.IsNull() ? number(node, key) : fallback;
}

bool YamlReader::flagOr(const YAML::Node& parent, const std::string& name, const std::string& key, bool fallback) const {
  const YAML::Node node = parent[name];
  if (!node.IsDefined() || node.IsNull()) return fallback;
  try {
    if (node.IsScalar()) return node.as<bool>();
  } catch (const YAML::Exception&) {
  }
  fail(node, key, "must be true or false");
}

std::vector<double> YamlReader::numbers(const YAML::Node& node, const std::string& key, std::size_t count) const {
  if (!node.IsSequence() || node.size() != count) {
    fail(node, key, "must be a list of " + std::to_string(count) + " numbers");
  }
  return numberList(node, key);
}

std::vector<double> YamlReader::numberList(const YAML::Node& node, const std::string& key) const {
  if (!node.IsSequence() || node.size() == 0) fail(node, key, "must be a list of numbers");
  std::vector<double> values;
  for (std::size_t i = 0; i < node.size(); ++i) values.push_back(number(node[i], key + "[" + std::to_string(i) + "]"));
  return values;
}

Eigen::Vector3d YamlReader::vector3(const YAML::Node& node, const std::string& key) const {
  const auto v = numbers(node, key, 3);
  return {v[0], v[1], v[2]};
}

void YamlReader::throwMalformed(const std::string& what, const YAML::Exception& e) const {
  throw InputError(source_ + ":" + std::to_string(e.mark.line + 1) + ": malformed " + what + " (" + e.msg + ")");
}

YAML::Node YamlReader::loadMap(const std::string& yaml_text, const std::string& what) const {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw InputError(source_ + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML (" + e.msg + ")");
  }
  if (!root.IsMap()) throw InputError(source_ + ": not " + what + " (expected a YAML map)");
  return root;
}

}  // namespace room_reverb::core
