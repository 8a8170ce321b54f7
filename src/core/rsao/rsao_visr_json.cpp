#include "room_reverb/rsao/rsao_visr_json.h"

#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>

#include "room_reverb/common/error.h"
#include "room_reverb/rsao/late_envelope.h"
#include "rsao_file_text.h"

namespace room_reverb::core {
namespace {

using rsao_text::fileDegrees;
using rsao_text::radiansFromFileDegrees;
using rsao_text::shortestDecimal;
using ordered_json = nlohmann::ordered_json;
using json = nlohmann::json;

const double kLn10 = std::log(10.0);
constexpr std::size_t kMaxSectionsPerReflection = 10;  // VISR's cNumDiscreteReflectionBiquads

// ---------------------------------------------------------------------------------------
// Export
// ---------------------------------------------------------------------------------------

void requireFinite(double value, const std::string& what) {
  if (!std::isfinite(value)) throw InputError("VISR export: " + what + " is not finite");
}

ordered_json sections(const std::vector<BiquadSection>& sos, const std::string& what) {
  if (sos.size() > kMaxSectionsPerReflection) {
    throw InputError("VISR export: " + what + " has " + std::to_string(sos.size()) +
                     " second-order sections; VISR takes at most 10 per reflection (refit with order <= 20)");
  }
  ordered_json list = ordered_json::array();
  for (const BiquadSection& s : sos) {
    for (double v : {s.b0, s.b1, s.b2, s.a1, s.a2}) requireFinite(v, what + "'s filter");
    list.push_back({{"b0", s.b0}, {"b1", s.b1}, {"b2", s.b2}, {"a0", 1.0}, {"a1", s.a1}, {"a2", s.a2}});
  }
  return list;
}

// VISR places a source at distance `radius` along its direction; 0 would put it at the
// listener, so an unknown distance (0) is written as VISR's default, 1 m.
double fileDistance(double distance_m) { return distance_m > 0.0 ? distance_m : 1.0; }

// Nine numbers as VISR's parser wants them: one string, comma-separated.
std::string bandString(const std::vector<double>& values) {
  std::string out;
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + shortestDecimal(values[i]);
  return out;
}

// ---------------------------------------------------------------------------------------
// Import: each accessor names the key path it reads.
// ---------------------------------------------------------------------------------------

[[noreturn]] void fail(const std::string& key, const std::string& message) {
  throw InputError("VISR JSON: " + key + ": " + message);
}

const json& require(const json& parent, const char* name, const std::string& key) {
  if (!parent.is_object()) fail(key, "expected an object holding '" + std::string(name) + "'");
  const auto it = parent.find(name);
  if (it == parent.end() || it->is_null()) fail(key, "missing");
  return *it;
}

// A number from its text, the whole text (blanks around it allowed).
bool parseNumber(std::string text, double& value) {
  const auto first = text.find_first_not_of(" \t\n\r");
  if (first == std::string::npos) return false;
  text = text.substr(first, text.find_last_not_of(" \t\n\r") - first + 1);
  if (!text.empty() && text.front() == '+') text.erase(0, 1);
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  return result.ec == std::errc() && result.ptr == text.data() + text.size();
}

// VISR writes numbers as strings; either form is accepted.
double numberValue(const json& node, const std::string& key) {
  double value = 0.0;
  if (node.is_number()) {
    value = node.get<double>();
  } else if (!(node.is_string() && parseNumber(node.get<std::string>(), value))) {
    fail(key, node.dump() + " is not a number");
  }
  if (!std::isfinite(value)) fail(key, "must be finite");
  return value;
}

double number(const json& parent, const char* name, const std::string& key) {
  return numberValue(require(parent, name, key), key);
}

double numberOr(const json& parent, const char* name, const std::string& key, double fallback) {
  const auto it = parent.find(name);
  return it == parent.end() || it->is_null() ? fallback : numberValue(*it, key);
}

int integerOr(const json& parent, const char* name, const std::string& key) {
  const double v = numberOr(parent, name, key, 0.0);
  if (v != std::floor(v) || std::abs(v) > 2.0e9) fail(key, "must be an integer");
  return static_cast<int>(v);
}

// The nine band values: VISR's comma-separated string, or a JSON array.
std::vector<double> bandValues(const json& parent, const char* name, const std::string& key) {
  const json& node = require(parent, name, key);
  std::vector<double> values;
  if (node.is_string()) {
    const std::string text = node.get<std::string>();
    std::size_t start = 0;
    while (start <= text.size()) {
      const std::size_t end = std::min(text.find(',', start), text.size());
      double v = 0.0;
      if (!parseNumber(text.substr(start, end - start), v)) {
        fail(key + "[" + std::to_string(values.size()) + "]", "'" + text.substr(start, end - start) + "' is not a number");
      }
      if (!std::isfinite(v)) fail(key + "[" + std::to_string(values.size()) + "]", "must be finite");
      values.push_back(v);
      start = end + 1;
    }
  } else if (node.is_array()) {
    for (std::size_t i = 0; i < node.size(); ++i) values.push_back(numberValue(node[i], key + "[" + std::to_string(i) + "]"));
  } else {
    fail(key, "must be a string of nine comma-separated numbers");
  }
  if (values.size() != static_cast<std::size_t>(kOctaveBandCount)) {
    fail(key, "has " + std::to_string(values.size()) + " values; VISR's late reverb has nine octave bands (63 Hz .. 16 kHz)");
  }
  return values;
}

std::vector<BiquadSection> readSections(const json& node, const std::string& key) {
  if (!node.is_array()) fail(key, "must be a list of biquads");
  if (node.size() > kMaxSectionsPerReflection) fail(key, "has more than 10 sections (VISR's limit)");
  std::vector<BiquadSection> out;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string k = key + "[" + std::to_string(i) + "]";
    const double a0 = numberOr(node[i], "a0", k + ".a0", 1.0);
    if (a0 == 0.0) fail(k + ".a0", "must not be zero");
    BiquadSection s;
    s.b0 = number(node[i], "b0", k + ".b0") / a0;
    s.b1 = number(node[i], "b1", k + ".b1") / a0;
    s.b2 = number(node[i], "b2", k + ".b2") / a0;
    s.a1 = number(node[i], "a1", k + ".a1") / a0;
    s.a2 = number(node[i], "a2", k + ".a2") / a0;
    out.push_back(s);
  }
  return out;
}

// What the project adds to a VISR reflection under its own key (VISR ignores it): the
// image source's position in the microphone's frame [m] and the estimate's confidence.
ordered_json reflectionExtras(const EarlyReflection& r) {
  // From the direction as the file gives it, so that a file read and written again holds
  // the same text.
  EarlyReflection as_read = r;
  as_read.azimuth_rad = radiansFromFileDegrees(fileDegrees(r.azimuth_rad));
  as_read.elevation_rad = radiansFromFileDegrees(fileDegrees(r.elevation_rad));
  as_read.distance_m = fileDistance(r.distance_m);
  const std::array<double, 3> image = imageSourcePosition(as_read);
  ordered_json extras = {{"image_source_m", {image[0], image[1], image[2]}}};
  if (r.confidence) extras["confidence"] = *r.confidence;
  return extras;
}

// The confidence in a reflection's "room_reverb" key, when it holds one in 0..1 (other
// programs' files may carry anything there: it is ignored then).
void readConfidence(const json& extras, EarlyReflection& r) {
  if (!extras.is_object() || !extras.contains("confidence") || !extras["confidence"].is_number()) return;
  const double c = extras["confidence"].get<double>();
  if (c >= 0.0 && c <= 1.0) r.confidence = c;
}

// Direction and distance from a VISR position: az, el (degrees) and radius (or refdist),
// or Cartesian x, y, z.
void readPosition(const json& parent, const std::string& key, EarlyReflection& r) {
  const json& p = require(parent, "position", key);
  if (p.contains("az") || p.contains("el")) {
    r.azimuth_rad = radiansFromFileDegrees(number(p, "az", key + ".az"));
    r.elevation_rad = radiansFromFileDegrees(number(p, "el", key + ".el"));
    r.distance_m = numberOr(p, "radius", key + ".radius", numberOr(p, "refdist", key + ".refdist", 1.0));
  } else {
    const double x = number(p, "x", key + ".x"), y = number(p, "y", key + ".y"), z = numberOr(p, "z", key + ".z", 0.0);
    r.distance_m = std::sqrt(x * x + y * y + z * z);
    if (!(r.distance_m > 0.0)) fail(key, "the position is the origin: no direction");
    r.azimuth_rad = std::atan2(y, x);
    r.elevation_rad = std::asin(z / r.distance_m);
  }
}

const json& selectObject(const json& root, int object_id) {
  if (!root.is_object()) fail("(root)", "expected a JSON object");
  if (!root.contains("objects")) return root;
  const json& objects = root["objects"];
  if (!objects.is_array()) fail("objects", "must be a list");
  for (const json& object : objects) {
    if (!object.is_object() || !object.contains("type") || object["type"] != "pointreverb") continue;
    if (object_id < 0) return object;
    if (object.contains("id") && numberValue(object["id"], "objects[].id") == object_id) return object;
  }
  fail("objects", object_id < 0 ? "no object of type pointreverb" : "no pointreverb object with id " + std::to_string(object_id));
}

// The Rsao and object fields of one pointreverb object.
VisrImport readObject(const json& object) {
  VisrImport out;
  out.fields.id = integerOr(object, "id", "id");
  out.fields.channel = integerOr(object, "channels", "channels");
  out.fields.group = integerOr(object, "group", "group");
  out.fields.priority = integerOr(object, "priority", "priority");
  out.fields.level = numberOr(object, "level", "level", 1.0);

  Rsao& rsao = out.rsao;
  EarlyReflection direct;
  direct.level = 1.0;
  readPosition(object, "position", direct);
  if (object.contains("biquadsos")) direct.sos = readSections(object["biquadsos"], "biquadsos");
  if (object.contains("room_reverb") && object["room_reverb"].is_object() && object["room_reverb"].contains("direct")) {
    readConfidence(object["room_reverb"]["direct"], direct);
  }
  rsao.reflections.push_back(direct);

  const json& room = require(object, "room", "room");
  if (room.contains("ereflect")) {
    const json& early = room["ereflect"];
    if (!early.is_array()) fail("room.ereflect", "must be a list");
    for (std::size_t k = 0; k < early.size(); ++k) {
      const std::string key = "room.ereflect[" + std::to_string(k) + "]";
      EarlyReflection r;
      r.time_of_arrival_s = number(early[k], "delay", key + ".delay");
      r.level = number(early[k], "level", key + ".level");
      readPosition(early[k], key + ".position", r);
      if (early[k].contains("biquadsos")) r.sos = readSections(early[k]["biquadsos"], key + ".biquadsos");
      if (early[k].contains("room_reverb")) readConfidence(early[k]["room_reverb"], r);
      rsao.reflections.push_back(r);
    }
  }

  const json& late = require(room, "lreverb", "room.lreverb");
  rsao.late.onset_s = number(late, "delay", "room.lreverb.delay");
  const std::vector<double> levels = bandValues(late, "level", "room.lreverb.level");
  const std::vector<double> decays = bandValues(late, "decayconst", "room.lreverb.decayconst");
  // VISR's older parser had no attack times: the decay then starts at the onset.
  const std::vector<double> attacks = late.contains("attacktime") ? bandValues(late, "attacktime", "room.lreverb.attacktime")
                                                                  : std::vector<double>(decays.size(), 0.0);
  rsao.late.attack_time_s = attacks.front();
  for (double a : attacks) {
    if (a != attacks.front()) {
      rsao.late.attack_time_s = std::max(rsao.late.attack_time_s, a);
      rsao.warnings.push_back("room.lreverb.attacktime differs between bands; the RSAO has one, the longest was taken");
      break;
    }
  }
  rsao.late.mixing_time_s = rsao.late.onset_s + rsao.late.attack_time_s;

  std::vector<bool> reliable(levels.size(), true);
  std::vector<std::string> reasons(levels.size());
  std::vector<double> onset_levels(levels.size(), 0.0);
  std::vector<LateReverbBand> slopes(levels.size());  // the two-slope fields only
  if (object.contains("room_reverb")) {
    const json& extra = object["room_reverb"];
    const json flags = extra.value("band_reliable", json::array());
    const json texts = extra.value("band_reason", json::array());
    const json onsets = extra.value("band_onset_level", json::array());
    for (std::size_t b = 0; b < levels.size(); ++b) {
      if (b < flags.size() && flags[b].is_boolean()) reliable[b] = flags[b].get<bool>();
      if (b < texts.size() && texts[b].is_string()) reasons[b] = texts[b].get<std::string>();
      if (b < onsets.size() && onsets[b].is_number()) onset_levels[b] = onsets[b].get<double>();
    }
    // A bent decay: [first decay constant, second decay constant, second share] per band.
    const json bent = extra.value("band_two_slopes", json::array());
    for (std::size_t b = 0; b < levels.size() && b < bent.size(); ++b) {
      const json& v = bent[b];
      if (!(v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number())) {
        fail("room_reverb.band_two_slopes[" + std::to_string(b) + "]",
             "must be [first decay constant, second decay constant, second share]");
      }
      slopes[b].first_decay_constant_per_s = v[0].get<double>();
      slopes[b].second_decay_constant_per_s = v[1].get<double>();
      slopes[b].second_share = v[2].get<double>();
      if (!slopesWellFormed(slopes[b])) {
        fail("room_reverb.band_two_slopes[" + std::to_string(b) + "]",
             "needs positive decay constants and a share in (0, 1) (or a share of 0: one slope)");
      }
    }
    if (extra.contains("course_end") && extra["course_end"].is_number()) rsao.late.course_end_s = extra["course_end"].get<double>();
  }
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  for (std::size_t b = 0; b < levels.size(); ++b) {
    if (!(decays[b] < 0.0)) {
      fail("room.lreverb.decayconst[" + std::to_string(b) + "]",
           "must be negative (VISR's late envelope is exp(decayconst * t)), got " + shortestDecimal(decays[b]));
    }
    LateReverbBand band;
    band.center_hz = bands[b].center_hz;
    band.decay_constant_per_s = -decays[b];
    band.t60_s = 3.0 * kLn10 / band.decay_constant_per_s;
    band.level = levels[b];
    band.onset_level = onset_levels[b];
    if (hasTwoSlopes(slopes[b])) {
      band.first_decay_constant_per_s = slopes[b].first_decay_constant_per_s;
      band.second_decay_constant_per_s = slopes[b].second_decay_constant_per_s;
      band.second_share = slopes[b].second_share;
    }
    band.reliable = reliable[b];
    band.reason = reasons[b];
    rsao.late.bands.push_back(band);
  }
  return out;
}

}  // namespace

std::string rsaoToVisrJson(const Rsao& rsao, const VisrObjectFields& fields, int indent) {
  if (rsao.reflections.empty()) throw InputError("VISR export: the RSAO has no direct sound (reflections[0])");
  const EarlyReflection& direct = rsao.reflections.front();
  if (!(direct.level > 0.0) || !std::isfinite(direct.level)) {
    throw InputError("VISR export: the direct sound's level must be positive (VISR levels are relative to it)");
  }
  if (rsao.late.bands.size() != static_cast<std::size_t>(kOctaveBandCount)) {
    throw InputError("VISR export: the late reverb has " + std::to_string(rsao.late.bands.size()) +
                     " bands; VISR needs the nine octave bands 63 Hz .. 16 kHz");
  }
  for (const EarlyReflection& r : rsao.reflections) {
    for (double v : {r.time_of_arrival_s, r.level, r.azimuth_rad, r.elevation_rad, r.distance_m}) requireFinite(v, "a reflection");
  }
  for (double v : {rsao.late.onset_s, rsao.late.attack_time_s}) requireFinite(v, "the late onset");

  ordered_json object;
  object["type"] = "pointreverb";
  object["id"] = fields.id;
  object["channels"] = fields.channel;
  object["group"] = fields.group;
  object["priority"] = fields.priority;
  object["level"] = fields.level.value_or(direct.level);
  object["position"] = {{"az", fileDegrees(direct.azimuth_rad)},
                        {"el", fileDegrees(direct.elevation_rad)},
                        {"radius", fileDistance(direct.distance_m)}};
  object["biquadsos"] = sections(direct.sos, "the direct sound");

  ordered_json early = ordered_json::array();
  for (std::size_t k = 1; k < rsao.reflections.size(); ++k) {
    const EarlyReflection& r = rsao.reflections[k];
    ordered_json e;
    e["delay"] = r.time_of_arrival_s - direct.time_of_arrival_s;
    e["level"] = r.level / direct.level;
    e["position"] = {{"az", fileDegrees(r.azimuth_rad)},
                     {"el", fileDegrees(r.elevation_rad)},
                     {"refdist", fileDistance(r.distance_m)}};
    e["biquadsos"] = sections(r.sos, "reflection " + std::to_string(k));
    e["room_reverb"] = reflectionExtras(r);
    early.push_back(e);
  }

  std::vector<double> levels, attacks, decays, onset_levels;
  ordered_json reliable = ordered_json::array(), reasons = ordered_json::array(), two_slopes = ordered_json::array();
  bool bent = false;
  for (const LateReverbBand& band : rsao.late.bands) {
    if (!(band.decay_constant_per_s > 0.0) || !std::isfinite(band.decay_constant_per_s) || !std::isfinite(band.level)) {
      throw InputError("VISR export: the late band at " + shortestDecimal(band.center_hz) +
                       " Hz needs a finite positive decay constant and a finite level");
    }
    levels.push_back(band.level / direct.level);
    attacks.push_back(rsao.late.attack_time_s);
    decays.push_back(-band.decay_constant_per_s);  // VISR: amplitude exp(decayconst * t)
    onset_levels.push_back(band.onset_level / direct.level);
    two_slopes.push_back({band.first_decay_constant_per_s, band.second_decay_constant_per_s, band.second_share});
    bent = bent || hasTwoSlopes(band);
    reliable.push_back(band.reliable);
    reasons.push_back(band.reason);
  }
  ordered_json late;
  late["delay"] = rsao.late.onset_s - direct.time_of_arrival_s;
  late["level"] = bandString(levels);
  late["attacktime"] = bandString(attacks);
  late["decayconst"] = bandString(decays);
  object["room"] = {{"ereflect", early}, {"lreverb", late}};
  object["room_reverb"] = {{"band_reliable", reliable}, {"band_reason", reasons}, {"band_onset_level", onset_levels},
                           {"course_end", rsao.late.course_end_s > 0.0 ? rsao.late.course_end_s - direct.time_of_arrival_s : 0.0},
                           {"direct", reflectionExtras(direct)}};
  if (bent) object["room_reverb"]["band_two_slopes"] = two_slopes;

  ordered_json scene;
  scene["objects"] = ordered_json::array({object});
  return scene.dump(indent);
}

VisrImport visrJsonToRsao(const std::string& json_text, int object_id) {
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number past double's range
    throw InputError(std::string("VISR JSON: not valid JSON (") + e.what() + ")");
  }
  try {
    return readObject(selectObject(root, object_id));
  } catch (const json::exception& e) {
    // The accessors turn expected faults into InputError; this catches the rest (a value
    // of an unexpected JSON type deep inside) so that no nlohmann exception leaves the core.
    throw InputError(std::string("VISR JSON: malformed pointreverb object (") + e.what() + ")");
  }
}

}  // namespace room_reverb::core
