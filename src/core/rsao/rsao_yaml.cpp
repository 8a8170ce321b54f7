#include "room_reverb/rsao/rsao_yaml.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/yaml_reader.h"
#include "room_reverb/rsao/late_envelope.h"
#include "rsao_file_text.h"

namespace room_reverb::core {
namespace {

using rsao_text::fileDegrees;
using rsao_text::radiansFromFileDegrees;
using rsao_text::shortestDecimal;

const double kLn10 = std::log(10.0);
constexpr const char* kFormat = "room_reverb_rsao";
constexpr int kVersion = 1;

// ---------------------------------------------------------------------------------------
// Writing, by hand: block maps for reflections, one flow map per band and section.
// ---------------------------------------------------------------------------------------

// YAML double-quoted scalar: backslash escapes for quote, backslash and control characters.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    switch (ch) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20) {
          char escape[8];
          std::snprintf(escape, sizeof escape, "\\x%02x", static_cast<unsigned>(static_cast<unsigned char>(ch)));
          out += escape;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

std::string numberList(const std::vector<double>& values) {
  std::string out = "[";
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + shortestDecimal(values[i]);
  return out + "]";
}

// Every number the file will hold must read back: no NaN or infinity.
void checkFinite(const Rsao& r) {
  auto check = [](double v, const std::string& key) {
    if (!std::isfinite(v)) throw InputError("rsao yaml: " + key + " is not finite; refusing to write a file that would not read back");
  };
  check(r.sample_rate_hz, "sample_rate_hz");
  check(r.duration_s, "duration_s");
  for (std::size_t k = 0; k < r.reflections.size(); ++k) {
    const EarlyReflection& e = r.reflections[k];
    const std::string key = "reflections[" + std::to_string(k) + "]";
    for (double v : {e.time_of_arrival_s, e.level, e.azimuth_rad, e.elevation_rad, e.distance_m, e.lpc_gain,
                     e.confidence.value_or(0.0)}) {
      check(v, key);
    }
    for (double v : e.lpc) check(v, key + ".lpc");
    for (const BiquadSection& s : e.sos) {
      for (double v : {s.b0, s.b1, s.b2, s.a1, s.a2}) check(v, key + ".sos");
    }
  }
  check(r.late.mixing_time_s, "late.mixing_time_s");
  check(r.late.onset_s, "late.onset_s");
  check(r.late.attack_time_s, "late.attack_time_s");
  check(r.late.course_end_s, "late.course_end_s");
  for (std::size_t b = 0; b < r.late.bands.size(); ++b) {
    const LateReverbBand& band = r.late.bands[b];
    for (double v : {band.center_hz, band.decay_constant_per_s, band.t60_s, band.level}) {
      check(v, "late.bands[" + std::to_string(b) + "]");
    }
  }
}

// ---------------------------------------------------------------------------------------
// Reading, over the project's YamlReader (each accessor names its key and line).
// ---------------------------------------------------------------------------------------

class Reader {
 public:
  explicit Reader(std::string source) : yaml_(std::move(source)) {}

  Rsao parse(const std::string& text) const {
    return yaml_.guarded("RSAO file", [&] { return parseUnguarded(text); });
  }

 private:
  double requiredNumber(const YAML::Node& parent, const std::string& name, const std::string& key) const {
    return yaml_.number(yaml_.require(parent, name, key), key);
  }

  // A string that may be empty (a band's reason).
  std::string textOrEmpty(const YAML::Node& parent, const std::string& name, const std::string& key) const {
    const YAML::Node node = parent[name];
    if (!node.IsDefined() || node.IsNull()) return "";
    if (!node.IsScalar()) yaml_.fail(node, key, "must be a string");
    return node.Scalar();
  }

  // A list that may be absent or empty.
  YAML::Node sequenceOr(const YAML::Node& parent, const std::string& name, const std::string& key) const {
    const YAML::Node node = parent[name];
    if (!node.IsDefined() || node.IsNull()) return YAML::Node(YAML::NodeType::Sequence);
    if (!node.IsSequence()) yaml_.fail(node, key, "must be a list");
    return node;
  }

  BiquadSection section(const YAML::Node& node, const std::string& key) const {
    yaml_.requireMap(node, key);
    BiquadSection s;
    s.b0 = requiredNumber(node, "b0", key + ".b0");
    s.b1 = requiredNumber(node, "b1", key + ".b1");
    s.b2 = requiredNumber(node, "b2", key + ".b2");
    s.a1 = requiredNumber(node, "a1", key + ".a1");
    s.a2 = requiredNumber(node, "a2", key + ".a2");
    return s;
  }

  EarlyReflection reflection(const YAML::Node& node, const std::string& key) const {
    yaml_.requireMap(node, key);
    EarlyReflection r;
    r.time_of_arrival_s = requiredNumber(node, "time_of_arrival_s", key + ".time_of_arrival_s");
    r.level = requiredNumber(node, "level", key + ".level");
    r.azimuth_rad = radiansFromFileDegrees(requiredNumber(node, "azimuth_deg", key + ".azimuth_deg"));
    r.elevation_rad = radiansFromFileDegrees(requiredNumber(node, "elevation_deg", key + ".elevation_deg"));
    r.distance_m = yaml_.numberOr(node, "distance_m", key + ".distance_m", 0.0);
    if (node["confidence"]) {
      r.confidence = yaml_.number(node["confidence"], key + ".confidence");
      if (!(*r.confidence >= 0.0 && *r.confidence <= 1.0)) {
        yaml_.fail(node["confidence"], key + ".confidence", "must lie in 0..1, got " + shortestDecimal(*r.confidence));
      }
    }
    // image_source_m is written for readers of the file; it follows from distance and
    // direction, which are what is read.
    const YAML::Node lpc = sequenceOr(node, "lpc", key + ".lpc");
    for (std::size_t i = 0; i < lpc.size(); ++i) r.lpc.push_back(yaml_.number(lpc[i], key + ".lpc[" + std::to_string(i) + "]"));
    if (!r.lpc.empty() && r.lpc.front() != 1.0) yaml_.fail(lpc, key + ".lpc", "the first coefficient of A(z) must be 1");
    r.lpc_gain = yaml_.numberOr(node, "lpc_gain", key + ".lpc_gain", 1.0);
    const YAML::Node sos = sequenceOr(node, "sos", key + ".sos");
    for (std::size_t i = 0; i < sos.size(); ++i) r.sos.push_back(section(sos[i], key + ".sos[" + std::to_string(i) + "]"));
    return r;
  }

  LateReverbBand band(const YAML::Node& node, const std::string& key) const {
    yaml_.requireMap(node, key);
    LateReverbBand b;
    b.center_hz = requiredNumber(node, "center_hz", key + ".center_hz");
    const bool has_delta = node["decay_constant_per_s"].IsDefined();
    const bool has_t60 = node["t60_s"].IsDefined();
    if (!has_delta && !has_t60) yaml_.fail(node, key, "needs decay_constant_per_s or t60_s");
    if (has_delta) b.decay_constant_per_s = requiredNumber(node, "decay_constant_per_s", key + ".decay_constant_per_s");
    if (has_t60) b.t60_s = requiredNumber(node, "t60_s", key + ".t60_s");
    if (!has_delta) b.decay_constant_per_s = 3.0 * kLn10 / b.t60_s;
    if (!has_t60) b.t60_s = 3.0 * kLn10 / b.decay_constant_per_s;
    if (std::abs(b.t60_s * b.decay_constant_per_s - 3.0 * kLn10) > 1e-6 * 3.0 * kLn10) {
      yaml_.fail(node, key, "t60_s and decay_constant_per_s disagree (t60 = 3 ln 10 / decay constant); give one of them");
    }
    b.level = requiredNumber(node, "level", key + ".level");
    b.onset_level = yaml_.numberOr(node, "onset_level", key + ".onset_level", 0.0);
    b.second_share = yaml_.numberOr(node, "second_share", key + ".second_share", 0.0);
    if (b.second_share != 0.0) {
      b.first_decay_constant_per_s = requiredNumber(node, "first_decay_constant_per_s", key + ".first_decay_constant_per_s");
      b.second_decay_constant_per_s = requiredNumber(node, "second_decay_constant_per_s", key + ".second_decay_constant_per_s");
      if (!slopesWellFormed(b)) {
        yaml_.fail(node, key, "has two slopes: second_share must lie in (0, 1) and both decay constants be positive");
      }
    }
    b.reliable = yaml_.flagOr(node, "reliable", key + ".reliable", true);
    b.reason = textOrEmpty(node, "reason", key + ".reason");
    return b;
  }

  Rsao parseUnguarded(const std::string& text) const {
    const YAML::Node root = yaml_.loadMap(text, "an RSAO file");
    const YAML::Node format = root["format"];
    if (format.IsDefined() && !format.IsNull() && yaml_.text(format, "format") != kFormat) {
      yaml_.fail(format, "format", "is '" + format.Scalar() + "', expected " + kFormat);
    }
    const YAML::Node version = root["version"];
    if (version.IsDefined() && !version.IsNull() && yaml_.number(version, "version") != kVersion) {
      yaml_.fail(version, "version", "this reader knows version " + std::to_string(kVersion) + " only");
    }
    Rsao r;
    r.sample_rate_hz = yaml_.numberOr(root, "sample_rate_hz", "sample_rate_hz", 48000.0);
    r.duration_s = yaml_.numberOr(root, "duration_s", "duration_s", 0.0);
    const YAML::Node reflections = yaml_.require(root, "reflections", "reflections");
    if (!reflections.IsSequence()) yaml_.fail(reflections, "reflections", "must be a list (empty: [])");
    for (std::size_t k = 0; k < reflections.size(); ++k) {
      r.reflections.push_back(reflection(reflections[k], "reflections[" + std::to_string(k) + "]"));
    }
    const YAML::Node late = yaml_.require(root, "late", "late");
    yaml_.requireMap(late, "late");
    r.late.mixing_time_s = requiredNumber(late, "mixing_time_s", "late.mixing_time_s");
    r.late.onset_s = requiredNumber(late, "onset_s", "late.onset_s");
    r.late.attack_time_s = requiredNumber(late, "attack_time_s", "late.attack_time_s");
    r.late.course_end_s = yaml_.numberOr(late, "course_end_s", "late.course_end_s", 0.0);
    const YAML::Node bands = yaml_.require(late, "bands", "late.bands");
    if (!bands.IsSequence() || (bands.size() != 0 && bands.size() != static_cast<std::size_t>(kOctaveBandCount))) {
      yaml_.fail(bands, "late.bands", "must be a list of the nine octave bands 63 Hz .. 16 kHz (or empty), has " +
                                          std::to_string(bands.IsSequence() ? bands.size() : 0));
    }
    for (std::size_t b = 0; b < bands.size(); ++b) r.late.bands.push_back(band(bands[b], "late.bands[" + std::to_string(b) + "]"));
    const YAML::Node warnings = sequenceOr(root, "warnings", "warnings");
    for (std::size_t i = 0; i < warnings.size(); ++i) {
      if (!warnings[i].IsScalar()) yaml_.fail(warnings[i], "warnings[" + std::to_string(i) + "]", "must be a string");
      r.warnings.push_back(warnings[i].Scalar());
    }
    return r;
  }

  YamlReader yaml_;
};

}  // namespace

std::string rsaoToYaml(const Rsao& r) {
  checkFinite(r);
  std::ostringstream out;
  out << "# room_reverb RSAO (reverberant spatial audio object): seconds, linear levels, degrees\n";
  out << "format: " << kFormat << "\n";
  out << "version: " << kVersion << "\n";
  out << "sample_rate_hz: " << shortestDecimal(r.sample_rate_hz) << "\n";
  out << "duration_s: " << shortestDecimal(r.duration_s) << "\n";
  if (r.reflections.empty()) {
    out << "reflections: []\n";
  } else {
    out << "reflections:  # [0] is the direct sound\n";
    for (const EarlyReflection& e : r.reflections) {
      out << "  - time_of_arrival_s: " << shortestDecimal(e.time_of_arrival_s) << "\n";
      out << "    level: " << shortestDecimal(e.level) << "\n";
      out << "    azimuth_deg: " << shortestDecimal(fileDegrees(e.azimuth_rad)) << "\n";
      out << "    elevation_deg: " << shortestDecimal(fileDegrees(e.elevation_rad)) << "\n";
      out << "    distance_m: " << shortestDecimal(e.distance_m) << "\n";
      // From the direction as the file gives it, so that a file read and written again
      // holds the same text.
      EarlyReflection as_read = e;
      as_read.azimuth_rad = radiansFromFileDegrees(fileDegrees(e.azimuth_rad));
      as_read.elevation_rad = radiansFromFileDegrees(fileDegrees(e.elevation_rad));
      const std::array<double, 3> image = imageSourcePosition(as_read);
      out << "    image_source_m: " << numberList({image[0], image[1], image[2]}) << "\n";
      if (e.confidence) out << "    confidence: " << shortestDecimal(*e.confidence) << "\n";
      out << "    lpc: " << numberList(e.lpc) << "\n";
      out << "    lpc_gain: " << shortestDecimal(e.lpc_gain) << "\n";
      if (e.sos.empty()) {
        out << "    sos: []\n";
      } else {
        out << "    sos:\n";
        for (const BiquadSection& s : e.sos) {
          out << "      - {b0: " << shortestDecimal(s.b0) << ", b1: " << shortestDecimal(s.b1)
              << ", b2: " << shortestDecimal(s.b2) << ", a1: " << shortestDecimal(s.a1)
              << ", a2: " << shortestDecimal(s.a2) << "}\n";
        }
      }
    }
  }
  out << "late:\n";
  out << "  mixing_time_s: " << shortestDecimal(r.late.mixing_time_s) << "\n";
  out << "  onset_s: " << shortestDecimal(r.late.onset_s) << "\n";
  out << "  attack_time_s: " << shortestDecimal(r.late.attack_time_s) << "\n";
  out << "  course_end_s: " << shortestDecimal(r.late.course_end_s) << "\n";
  if (r.late.bands.empty()) {
    out << "  bands: []\n";
  } else {
    out << "  bands:\n";
    for (const LateReverbBand& b : r.late.bands) {
      out << "    - {center_hz: " << shortestDecimal(b.center_hz)
          << ", decay_constant_per_s: " << shortestDecimal(b.decay_constant_per_s)
          << ", t60_s: " << shortestDecimal(b.t60_s) << ", level: " << shortestDecimal(b.level)
          << ", onset_level: " << shortestDecimal(b.onset_level);
      if (hasTwoSlopes(b)) {
        out << ", first_decay_constant_per_s: " << shortestDecimal(b.first_decay_constant_per_s)
            << ", second_decay_constant_per_s: " << shortestDecimal(b.second_decay_constant_per_s)
            << ", second_share: " << shortestDecimal(b.second_share);
      }
      out << ", reliable: " << (b.reliable ? "true" : "false") << ", reason: " << quoted(b.reason) << "}\n";
    }
  }
  if (r.warnings.empty()) {
    out << "warnings: []\n";
  } else {
    out << "warnings:\n";
    for (const std::string& w : r.warnings) out << "  - " << quoted(w) << "\n";
  }
  return out.str();
}

Rsao parseRsaoYaml(const std::string& yaml_text, const std::string& source) { return Reader(source).parse(yaml_text); }

void saveRsaoYaml(const std::string& path, const Rsao& rsao) { writeTextFile(path, rsaoToYaml(rsao)); }

Rsao loadRsaoYaml(const std::string& path) { return Reader(path).parse(readTextFile(path, "RSAO YAML file")); }

}  // namespace room_reverb::core
