#include "room_reverb/evaluation/measurements.h"

#include <cmath>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/yaml_reader.h"

namespace room_reverb::core {
namespace {

std::string resolve(const std::string& base_directory, const std::string& path) {
  if (path.empty() || path.front() == '/' || base_directory.empty()) return path;
  return base_directory + "/" + path;
}

class MeasurementsReader : public YamlReader {
 public:
  MeasurementsReader(std::string source, std::string base) : YamlReader(std::move(source)), base_(std::move(base)) {}

  Measurements parse(const std::string& yaml_text) const {
    return guarded("measurements", [&] { return parseUnguarded(yaml_text); });
  }

 private:
  Measurements parseUnguarded(const std::string& yaml_text) const {
    const YAML::Node root = loadMap(yaml_text, "a measurements file with pairs and/or parameters");
    Measurements m;
    m.room_file = resolve(base_, textOr(root, "room", "room", ""));
    m.mesh_file = resolve(base_, textOr(root, "mesh", "mesh", ""));
    if (!m.room_file.empty() && !m.mesh_file.empty()) fail(root["mesh"], "mesh", "give a room or a mesh, not both");
    const std::string up = textOr(root, "mesh_up_axis", "mesh_up_axis", "z");
    if (up != "y" && up != "z") fail(root["mesh_up_axis"], "mesh_up_axis", "must be y or z (got " + up + ")");
    m.mesh_up_axis = up == "y" ? UpAxis::kY : UpAxis::kZ;
    if (root["air"].IsDefined()) {
      const YAML::Node air = root["air"];
      requireMap(air, "air");
      AirConditions a;
      a.enabled = flagOr(air, "enabled", "air.enabled", a.enabled);
      a.temperature_c = numberOr(air, "temperature_c", "air.temperature_c", a.temperature_c);
      a.humidity_percent = numberOr(air, "humidity_percent", "air.humidity_percent", a.humidity_percent);
      a.pressure_kpa = numberOr(air, "pressure_kpa", "air.pressure_kpa", a.pressure_kpa);
      if (!(a.humidity_percent >= 0.0 && a.humidity_percent <= 100.0)) fail(air, "air.humidity_percent", "must be in [0, 100]");
      m.air = a;
    }
    if (root["pairs"].IsDefined()) readPairs(root["pairs"], m.pairs);
    if (root["parameters"].IsDefined()) m.parameters = readParameters(root["parameters"]);
    if (m.pairs.empty() && m.parameters.empty()) fail(root, "pairs", "a measurements file needs pairs, parameters or both");
    return m;
  }

  void readPairs(const YAML::Node& node, std::vector<MeasurementPair>& pairs) const {
    if (!node.IsSequence() || node.size() == 0) fail(node, "pairs", "must be a list of source-receiver pairs");
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string key = "pairs[" + std::to_string(i) + "]";
      const YAML::Node p = node[i];
      requireMap(p, key);
      MeasurementPair pair;
      pair.label = textOr(p, "label", key + ".label", "");
      pair.file = resolve(base_, textOr(p, "file", key + ".file", ""));
      pair.format = textOr(p, "format", key + ".format", pair.file.empty() ? "" : "omni");
      if (!pair.format.empty() && pair.format != "omni" && pair.format != "fuma" && pair.format != "ambix") {
        fail(p["format"], key + ".format", "must be omni, fuma or ambix (got " + pair.format + ")");
      }
      pair.source_m = vector3(require(p, "source_m", key + ".source_m"), key + ".source_m");
      pair.receiver_m = vector3(require(p, "receiver_m", key + ".receiver_m"), key + ".receiver_m");
      pairs.push_back(pair);
    }
  }

  MeasuredParameters readParameters(const YAML::Node& node) const {
    requireMap(node, "parameters");
    MeasuredParameters p;
    const std::string resolution = textOr(node, "resolution", "parameters.resolution", "octave");
    try {
      p.resolution = parseBandResolution(resolution);
    } catch (const InputError&) {
      fail(node["resolution"], "parameters.resolution", "must be octave or third (got " + resolution + ")");
    }
    p.bands_hz = numberList(require(node, "bands_hz", "parameters.bands_hz"), "parameters.bands_hz");
    const std::size_t n = p.bands_hz.size();
    const auto row = [&](const char* name) -> std::vector<double> {
      const YAML::Node r = node[name];
      if (!r.IsDefined() || r.IsNull()) return {};
      return numbers(r, std::string("parameters.") + name, n);
    };
    p.t20_s = row("t20_s");
    p.t30_s = row("t30_s");
    p.edt_s = row("edt_s");
    p.c50_db = row("c50_db");
    p.c80_db = row("c80_db");
    p.d50 = row("d50");
    p.ts_s = row("ts_s");
    p.drr_db = row("drr_db");
    const std::vector<double> percent = row("d50_percent");
    if (!percent.empty()) {
      if (!p.d50.empty()) fail(node["d50_percent"], "parameters.d50_percent", "give d50 or d50_percent, not both");
      for (double v : percent) p.d50.push_back(v / 100.0);
    }
    for (double v : p.d50) {
      if (v < 0.0 || v > 1.0) fail(node, "parameters.d50", "D50 must be in [0, 1] (or 0-100 as d50_percent)");
    }
    return p;
  }

  std::string base_;
};

}  // namespace

bool isBFormat(const MeasurementPair& pair) { return pair.format == "fuma" || pair.format == "ambix"; }

MeasuredParameters parametersFromReport(const MetricsReport& report) {
  MeasuredParameters p;
  p.resolution = report.resolution;
  const auto value = [](const std::optional<double>& v) { return v ? *v : std::nan(""); };
  for (const AcousticParameters& band : report.bands) {
    p.bands_hz.push_back(band.nominal_hz);
    p.t20_s.push_back(value(band.t20_s));
    p.t30_s.push_back(value(band.t30_s));
    p.edt_s.push_back(value(band.edt_s));
    p.c50_db.push_back(value(band.c50_db));
    p.c80_db.push_back(value(band.c80_db));
    p.d50.push_back(value(band.d50));
    p.ts_s.push_back(value(band.ts_s));
    p.drr_db.push_back(value(band.drr_db));
  }
  return p;
}

Measurements parseMeasurements(const std::string& yaml_text, const std::string& base_directory) {
  return MeasurementsReader("measurements", base_directory).parse(yaml_text);
}

Measurements loadMeasurements(const std::string& path) {
  const std::string text = readTextFile(path, "measurements file");
  const auto slash = path.find_last_of('/');
  const std::string base = slash == std::string::npos ? "." : path.substr(0, slash);
  return MeasurementsReader(path, base).parse(text);
}

}  // namespace room_reverb::core
