#include "room_reverb/acoustics/material.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <tuple>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"

namespace room_reverb::core {
namespace {

// Nominal octave centres the nine coefficients refer to; a library written for other bands
// would silently be misread, so load() insists on exactly these.
constexpr std::array<double, kOctaveBandCount> kNominalOctavesHz = {63,   125,  250,  500,  1000,
                                                                    2000, 4000, 8000, 16000};

// Keys every material entry must have (see the header comment of config/materials.yaml).
// Third-octave coefficients, where given, run 20 Hz .. 20 kHz (config/materials.yaml's
// third_octave_centers_hz): the octaves' thirds 50 Hz .. 20 kHz start at the fifth.
constexpr std::size_t kThirdOctaveValueCount = 31;
constexpr std::size_t kFirstThirdOfTheOctaves = 4;

constexpr std::array<const char*, 4> kRequiredMaterialKeys = {"description", "absorption",
                                                              "scattering", "source"};

std::string formatNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return text;
}

std::string nodeLocation(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  if (mark.line < 0) return "";
  return " (line " + std::to_string(mark.line + 1) + ")";
}

void checkCoefficients(const std::string& name, const char* what, const OctaveBandValues& values) {
  for (int band = 0; band < kOctaveBandCount; ++band) {
    const double value = values[static_cast<std::size_t>(band)];
    if (std::isfinite(value) && value >= 0.0 && value <= 1.0) continue;
    throw InputError("material '" + name + "': " + what + " at " +
                     formatNumber(kNominalOctavesHz[static_cast<std::size_t>(band)]) + " Hz is " +
                     formatNumber(value) + ", must be a finite number in [0, 1]");
  }
}

// Reads a YAML sequence of exactly nine numbers; `context` prefixes every message so the
// user can find the offending entry.
OctaveBandValues readBandValues(const YAML::Node& node, const std::string& context) {
  if (!node.IsSequence()) {
    throw InputError(context + " must be a list of " + std::to_string(kOctaveBandCount) +
                     " numbers (63 Hz .. 16 kHz)" + nodeLocation(node));
  }
  if (node.size() != static_cast<std::size_t>(kOctaveBandCount)) {
    throw InputError(context + " has " + std::to_string(node.size()) + " values, expected " +
                     std::to_string(kOctaveBandCount) + " (63 Hz .. 16 kHz)" + nodeLocation(node));
  }
  OctaveBandValues values{};
  for (std::size_t i = 0; i < values.size(); ++i) {
    try {
      values[i] = node[i].as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(context + " value " + std::to_string(i + 1) + " is not a number" +
                       nodeLocation(node[i]));
    }
  }
  return values;
}

// Reads an optional list of the 31 third-octave values (20 Hz .. 20 kHz) into the thirds
// of the nine octaves.
std::optional<ThirdOctaveValues> readThirdOctaveValues(const YAML::Node& node, const std::string& context) {
  if (!node) return std::nullopt;
  if (!node.IsSequence() || node.size() != kThirdOctaveValueCount) {
    throw InputError(context + " must be a list of " + std::to_string(kThirdOctaveValueCount) +
                     " numbers (third octaves 20 Hz .. 20 kHz)" + nodeLocation(node));
  }
  std::array<double, kThirdOctaveValueCount> all{};
  for (std::size_t i = 0; i < all.size(); ++i) {
    try {
      all[i] = node[i].as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(context + " value " + std::to_string(i + 1) + " is not a number" + nodeLocation(node[i]));
    }
    if (!std::isfinite(all[i]) || all[i] < 0.0 || all[i] > 1.0) {
      throw InputError(context + " value " + std::to_string(i + 1) + " is " + formatNumber(all[i]) +
                       ", must be a finite number in [0, 1]" + nodeLocation(node[i]));
    }
  }
  ThirdOctaveValues values{};
  for (std::size_t b = 0; b < static_cast<std::size_t>(kOctaveBandCount); ++b) {
    for (std::size_t k = 0; k < 3; ++k) values[k][b] = all[kFirstThirdOfTheOctaves + 3 * b + k];
  }
  return values;
}

std::string readScalarString(const YAML::Node& entry, const char* key, const std::string& context) {
  const YAML::Node node = entry[key];
  if (!node.IsScalar()) {
    throw InputError(context + ": '" + key + "' must be a text value" + nodeLocation(entry));
  }
  return node.as<std::string>();
}

void checkBands(const YAML::Node& root, const std::string& path) {
  const YAML::Node bands = root["bands_hz"];
  if (!bands) throw InputError(path + ": missing 'bands_hz' (the nine octave centres)");
  const std::string expected = "[63, 125, 250, 500, 1000, 2000, 4000, 8000, 16000]";
  bool matches = bands.IsSequence() && bands.size() == kNominalOctavesHz.size();
  for (std::size_t i = 0; matches && i < kNominalOctavesHz.size(); ++i) {
    try {
      matches = bands[i].as<double>() == kNominalOctavesHz[i];
    } catch (const YAML::Exception&) {
      matches = false;
    }
  }
  if (!matches) {
    throw InputError(path + ": bands_hz must be " + expected + nodeLocation(bands));
  }
}

AcousticMaterial parseMaterial(const std::string& name, const YAML::Node& entry,
                               const std::string& path) {
  const std::string context = path + ": material '" + name + "'";
  if (!entry.IsMap()) {
    throw InputError(context + " must be a mapping with description, absorption, " +
                     "scattering and source" + nodeLocation(entry));
  }
  for (const char* key : kRequiredMaterialKeys) {
    if (!entry[key]) {
      throw InputError(context + " has no '" + key + "'" + nodeLocation(entry));
    }
  }
  AcousticMaterial material;
  material.name = name;
  material.absorption = readBandValues(entry["absorption"], context + ": absorption");
  material.scattering = readBandValues(entry["scattering"], context + ": scattering");
  material.absorption_thirds = readThirdOctaveValues(entry["absorption_third_octave"], context + ": absorption_third_octave");
  material.scattering_thirds = readThirdOctaveValues(entry["scattering_third_octave"], context + ": scattering_third_octave");
  material.source = readScalarString(entry, "source", context);
  readScalarString(entry, "description", context);  // required, but not kept in the struct
  try {
    validateMaterial(material);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what() + nodeLocation(entry));
  }
  return material;
}

// Levenshtein distance; names are short, so the O(n m) table is cheap.
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> previous(b.size() + 1);
  std::vector<std::size_t> current(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
    }
    std::swap(previous, current);
  }
  return previous[b.size()];
}

std::size_t longestCommonSubstring(const std::string& a, const std::string& b) {
  std::size_t best = 0;
  std::vector<std::size_t> previous(b.size() + 1, 0);
  std::vector<std::size_t> current(b.size() + 1, 0);
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      current[j] = a[i - 1] == b[j - 1] ? previous[j - 1] + 1 : 0;
      best = std::max(best, current[j]);
    }
    std::swap(previous, current);
  }
  return best;
}

// Up to five names the user may have meant. A candidate qualifies if it is a few edits
// away (typos) or shares a run of at least four characters (e.g. "concrete" for
// "mat_CR2_concrete"); typo matches come first because they are the likelier intent.
std::vector<std::string> closeNames(const std::string& wanted,
                                    const std::vector<std::string>& candidates) {
  const std::string key = lower(wanted);
  const std::size_t max_edits = std::max<std::size_t>(2, key.size() / 3);
  const std::size_t min_shared = std::min<std::size_t>(4, key.size());
  using Ranked = std::tuple<int, long, std::string>;
  std::vector<Ranked> ranked;
  for (const std::string& candidate : candidates) {
    const std::string other = lower(candidate);
    const std::size_t edits = editDistance(key, other);
    if (edits <= max_edits) {
      ranked.emplace_back(0, static_cast<long>(edits), candidate);
      continue;
    }
    const std::size_t shared = longestCommonSubstring(key, other);
    if (min_shared > 0 && shared >= min_shared) {
      // Longer shared runs first, then fewer edits as a tie break.
      ranked.emplace_back(1, -static_cast<long>(shared * 1000) + static_cast<long>(edits),
                          candidate);
    }
  }
  std::sort(ranked.begin(), ranked.end());
  std::vector<std::string> names;
  for (std::size_t i = 0; i < ranked.size() && i < 5; ++i) names.push_back(std::get<2>(ranked[i]));
  return names;
}

}  // namespace

void validateMaterial(const AcousticMaterial& material) {
  checkCoefficients(material.name, "absorption", material.absorption);
  checkCoefficients(material.name, "scattering", material.scattering);
  const char* third_names[3] = {"lower third", "centre third", "upper third"};
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string absorption = std::string("absorption (") + third_names[k] + ")";
    const std::string scattering = std::string("scattering (") + third_names[k] + ")";
    if (material.absorption_thirds) checkCoefficients(material.name, absorption.c_str(), (*material.absorption_thirds)[k]);
    if (material.scattering_thirds) checkCoefficients(material.name, scattering.c_str(), (*material.scattering_thirds)[k]);
  }
}

const OctaveBandValues& octaveCentresHz() {
  static const OctaveBandValues centres = [] {
    OctaveBandValues out{};
    const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
    for (int b = 0; b < kOctaveBandCount; ++b) out[b] = bands[static_cast<std::size_t>(b)].center_hz;
    return out;
  }();
  return centres;
}

AcousticMaterial thirdOctaveMaterial(const AcousticMaterial& material, int third) {
  if (third < 0 || third > 2) throw InputError("a third of an octave is 0, 1 or 2 (got " + std::to_string(third) + ")");
  AcousticMaterial out = material;
  const auto k = static_cast<std::size_t>(third);
  if (material.absorption_thirds) out.absorption = (*material.absorption_thirds)[k];
  if (material.scattering_thirds) out.scattering = (*material.scattering_thirds)[k];
  out.absorption_thirds.reset();
  out.scattering_thirds.reset();
  return out;
}

MaterialLibrary MaterialLibrary::load(const std::string& path) {
  // Checked first so the message says "no such file" rather than a YAML parser error.
  requireExistingFile(path, "material library", "set ROOM_REVERB_MATERIALS or pass an existing materials.yaml");

  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw InputError(path + ": malformed YAML at line " + std::to_string(e.mark.line + 1) + ": " +
                     e.msg);
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": cannot read material library: " + e.what());
  }
  if (!root.IsMap()) {
    throw InputError(path +
                     ": a material library must be a mapping with bands_hz, materials "
                     "and aliases");
  }
  // Scalars of the wrong type (a list as a key, say) surface as yaml-cpp exceptions; turn
  // them into InputError so callers only ever see one error type for a bad file.
  try {
    checkBands(root, path);

    const YAML::Node materials = root["materials"];
    if (!materials || !materials.IsMap() || materials.size() == 0) {
      throw InputError(path + ": 'materials' must be a non-empty mapping of name -> material");
    }
    MaterialLibrary library;
    for (const auto& item : materials) {
      const std::string name = item.first.as<std::string>();
      if (name.empty()) {
        throw InputError(path + ": a material has an empty name" + nodeLocation(item.first));
      }
      // yaml-cpp keeps both copies of a repeated key; a second entry would otherwise quietly
      // replace the first one.
      if (library.materials_.count(name) != 0) {
        throw InputError(path + ": material '" + name + "' is defined twice" +
                         nodeLocation(item.first));
      }
      library.materials_[name] = parseMaterial(name, item.second, path);
    }

    const YAML::Node aliases = root["aliases"];
    if (aliases && !aliases.IsNull()) {
      if (!aliases.IsMap()) {
        throw InputError(path + ": 'aliases' must be a mapping of alias -> material name" +
                         nodeLocation(aliases));
      }
      for (const auto& item : aliases) {
        const std::string alias = item.first.as<std::string>();
        if (!item.second.IsScalar()) {
          throw InputError(path + ": alias '" + alias + "' must name one material" +
                           nodeLocation(item.second));
        }
        const std::string target = item.second.as<std::string>();
        // Only keys are valid targets, as the file format says; chains of aliases would make
        // the file harder to check by eye.
        if (library.materials_.count(target) == 0) {
          throw InputError(path + ": alias '" + alias + "' points to unknown material '" + target +
                           "'" + nodeLocation(item.second));
        }
        if (library.materials_.count(alias) != 0) {
          throw InputError(path + ": alias '" + alias + "' is also a material name" +
                           nodeLocation(item.first));
        }
        if (library.aliases_.count(alias) != 0) {
          throw InputError(path + ": alias '" + alias + "' is defined twice" +
                           nodeLocation(item.first));
        }
        library.aliases_[alias] = target;
      }
    }
    return library;
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": unexpected content: " + e.what());
  }
}

MaterialLibrary MaterialLibrary::loadDefault() { return load(defaultPath()); }

std::string MaterialLibrary::defaultPath() {
  return packageFilePath("ROOM_REVERB_MATERIALS", "config/materials.yaml");
}

void MaterialLibrary::add(const AcousticMaterial& material) {
  if (material.name.empty()) throw InputError("a material needs a non-empty name");
  validateMaterial(material);
  // A material with an alias's name takes the name over, so get() finds what was added.
  aliases_.erase(material.name);
  materials_[material.name] = material;
}

void MaterialLibrary::addAlias(const std::string& alias, const std::string& target) {
  if (alias.empty()) throw InputError("an alias needs a non-empty name");
  if (materials_.count(alias) != 0) {
    throw InputError("alias '" + alias + "' is already a material name");
  }
  // Resolve through an existing alias so that lookups stay a single step.
  const auto via_alias = aliases_.find(target);
  const std::string key = via_alias != aliases_.end() ? via_alias->second : target;
  if (materials_.count(key) == 0) {
    throw InputError("alias '" + alias + "' points to unknown material '" + target + "'");
  }
  aliases_[alias] = key;
}

bool MaterialLibrary::contains(const std::string& name) const {
  return materials_.count(name) != 0 || aliases_.count(name) != 0;
}

const AcousticMaterial& MaterialLibrary::get(const std::string& name) const {
  const auto found = materials_.find(name);
  if (found != materials_.end()) return found->second;
  const auto alias = aliases_.find(name);
  if (alias != aliases_.end()) {
    const auto target = materials_.find(alias->second);
    if (target != materials_.end()) return target->second;
  }

  std::vector<std::string> candidates = names();
  for (const auto& entry : aliases_) candidates.push_back(entry.first);
  const std::vector<std::string> close = closeNames(name, candidates);
  std::string message = "unknown material '" + name + "'";
  if (close.empty()) {
    message += " (no similar name among the " + std::to_string(materials_.size()) +
               " materials and " + std::to_string(aliases_.size()) + " aliases)";
  } else {
    message += "; close names: ";
    for (std::size_t i = 0; i < close.size(); ++i) message += (i ? ", " : "") + close[i];
  }
  throw InputError(message);
}

std::vector<std::string> MaterialLibrary::names() const {
  std::vector<std::string> keys;
  keys.reserve(materials_.size());
  for (const auto& entry : materials_) keys.push_back(entry.first);
  return keys;  // std::map iterates in sorted order
}

}  // namespace room_reverb::core
