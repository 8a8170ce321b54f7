#include "arguments.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "command.h"

namespace room_reverb::tool {

Arguments::Arguments(const std::vector<std::string>& args, const std::set<std::string>& valued,
                     const std::set<std::string>& flags) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg.rfind("--", 0) != 0 || arg == "--") {
      positional_.push_back(arg);
      continue;
    }
    std::string name = arg.substr(2);
    std::string value;
    const auto equals = name.find('=');
    const bool inline_value = equals != std::string::npos;
    if (inline_value) {
      value = name.substr(equals + 1);
      name = name.substr(0, equals);
    }
    if (flags.count(name)) {
      if (inline_value) throw UsageError("--" + name + " takes no value");
      values_[name] = "";
    } else if (valued.count(name)) {
      if (!inline_value) {
        if (i + 1 >= args.size()) throw UsageError("--" + name + " needs a value");
        value = args[++i];
      }
      values_[name] = value;
    } else {
      throw UsageError("unknown option --" + name);
    }
  }
}

std::string Arguments::value(const std::string& name, const std::string& fallback) const {
  const auto found = values_.find(name);
  return found == values_.end() ? fallback : found->second;
}

int Arguments::intValue(const std::string& name, int fallback) const {
  if (!has(name)) return fallback;
  const std::string text = value(name, "");
  char* end = nullptr;
  errno = 0;
  const long parsed = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0') throw UsageError("--" + name + " needs an integer, got '" + text + "'");
  // Checked before the narrowing, which would wrap 4294967296 to 0.
  if (errno == ERANGE || parsed < std::numeric_limits<int>::min() || parsed > std::numeric_limits<int>::max()) {
    throw UsageError("--" + name + " is out of range, got '" + text + "'");
  }
  return static_cast<int>(parsed);
}

double Arguments::doubleValue(const std::string& name, double fallback) const {
  if (!has(name)) return fallback;
  const std::string text = value(name, "");
  char* end = nullptr;
  const double parsed = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') throw UsageError("--" + name + " needs a number, got '" + text + "'");
  return parsed;
}

std::optional<Eigen::Vector3d> takeVector(std::vector<std::string>& args, const std::string& name) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] != "--" + name) continue;
    if (i + 3 >= args.size()) throw UsageError("--" + name + " needs three numbers X Y Z");
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) {
      const std::string& text = args[i + 1 + static_cast<std::size_t>(k)];
      char* end = nullptr;
      v[k] = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0') throw UsageError("--" + name + " needs three numbers, got '" + text + "'");
      if (!std::isfinite(v[k])) throw UsageError("--" + name + " needs finite numbers, got '" + text + "'");
    }
    args.erase(args.begin() + static_cast<long>(i), args.begin() + static_cast<long>(i) + 4);
    return v;
  }
  return std::nullopt;
}

Eigen::Vector3d takeRequiredVector(std::vector<std::string>& args, const std::string& name) {
  const std::optional<Eigen::Vector3d> v = takeVector(args, name);
  if (!v) throw UsageError("--" + name + " X Y Z is required");
  return *v;
}

std::vector<std::string> commaSeparated(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  for (std::string item; std::getline(stream, item, ',');) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

}  // namespace room_reverb::tool
