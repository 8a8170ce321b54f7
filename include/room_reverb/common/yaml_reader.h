#pragma once
// Reading YAML documents with errors a user can act on: every accessor names the key it
// reads (and the line, when yaml-cpp knows it) and throws InputError, so no yaml-cpp
// exception leaves the core. Shared by the readers of the project's file formats.
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace room_reverb::core {

class YamlReader {
 public:
  explicit YamlReader(std::string source) : source_(std::move(source)) {}
  const std::string& source() const { return source_; }

  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& message) const;
  YAML::Node require(const YAML::Node& parent, const std::string& name, const std::string& key,
                     const std::string& why = "missing") const;
  void requireMap(const YAML::Node& node, const std::string& key) const;
  std::string text(const YAML::Node& node, const std::string& key) const;
  std::string textOr(const YAML::Node& parent, const std::string& name, const std::string& key,
                     const std::string& fallback) const;
  double number(const YAML::Node& node, const std::string& key) const;
  double numberOr(const YAML::Node& parent, const std::string& name, const std::string& key, double fallback) const;
  bool flagOr(const YAML::Node& parent, const std::string& name, const std::string& key, bool fallback) const;
  // A list of exactly `count` numbers.
  std::vector<double> numbers(const YAML::Node& node, const std::string& key, std::size_t count) const;
  // A list of any length (at least one) of numbers.
  std::vector<double> numberList(const YAML::Node& node, const std::string& key) const;
  Eigen::Vector3d vector3(const YAML::Node& node, const std::string& key) const;

  // Runs `parse`, turning any yaml-cpp exception the accessors did not anticipate (a map
  // used as a key, say) into an InputError naming `what`, so none leaves the core.
  template <class Parse>
  auto guarded(const std::string& what, Parse&& parse) const -> decltype(parse()) {
    try {
      return parse();
    } catch (const YAML::Exception& e) {
      throwMalformed(what, e);
    }
  }

  // Parses `yaml_text` (InputError with the line when it is not YAML) and requires a map.
  YAML::Node loadMap(const std::string& yaml_text, const std::string& what) const;

 private:
  [[noreturn]] void throwMalformed(const std::string& what, const YAML::Exception& e) const;
  std::string source_;
};

}  // namespace room_reverb::core
