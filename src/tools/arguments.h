#pragma once
// A small command-line parser: positional arguments and --options with or without values.
#include <Eigen/Core>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace room_reverb::tool {

class Arguments {
 public:
  // `valued`: options that take a value (--name VALUE or --name=VALUE); `flags`: options
  // without one. Anything else starting with "--" is a UsageError.
  Arguments(const std::vector<std::string>& args, const std::set<std::string>& valued,
            const std::set<std::string>& flags);

  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string value(const std::string& name, const std::string& fallback) const;
  int intValue(const std::string& name, int fallback) const;
  double doubleValue(const std::string& name, double fallback) const;
  const std::vector<std::string>& positional() const { return positional_; }

 private:
  std::map<std::string, std::string> values_;
  std::vector<std::string> positional_;
};

// Takes "--name X Y Z" out of `args` and returns the three numbers; none when the option
// is absent. UsageError unless three finite numbers follow it.
std::optional<Eigen::Vector3d> takeVector(std::vector<std::string>& args, const std::string& name);
// The same, for an option that must be there.
Eigen::Vector3d takeRequiredVector(std::vector<std::string>& args, const std::string& name);

// The items of a comma-separated option value ("a,b,c"), empty items left out.
std::vector<std::string> commaSeparated(const std::string& text);

}  // namespace room_reverb::tool
