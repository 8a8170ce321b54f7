#include "room_reverb/synthetic_capture/capture_scene.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/yaml_reader.h"

namespace room_reverb::core {
namespace {

class CaptureSectionReader : public YamlReader {
 public:
  using YamlReader::YamlReader;

  void read(const std::string& yaml_text, CaptureOptions& options) const {
    guarded("capture scene", [&] {
      const YAML::Node root = loadMap(yaml_text, "a room model with an optional capture section");
      const YAML::Node capture = root["capture"];
      if (!capture.IsDefined() || capture.IsNull()) return;
      requireMap(capture, "capture");
      for (const auto& entry : capture) {
        const std::string key = entry.first.as<std::string>();
        if (!isKnown(key)) {
          // A misspelt key would silently render with the default.
          fail(entry.first, "capture." + key,
               "unknown key (use baseline_m, width, supersampling, seed, shading, noise_sigma, fisheye, "
               "low_texture_materials, low_texture_contrast)");
        }
      }
      options.baseline_m = numberOr(capture, "baseline_m", "capture.baseline_m", options.baseline_m);
      options.width = wholeNumber(capture, "width", options.width);
      options.supersampling = wholeNumber(capture, "supersampling", options.supersampling);
      if (capture["seed"].IsDefined()) {
        const double seed = number(capture["seed"], "capture.seed");
        if (seed < 0.0 || seed != std::floor(seed) || seed > 9007199254740992.0) {
          fail(capture["seed"], "capture.seed", "must be a whole number >= 0");
        }
        options.seed = static_cast<std::uint64_t>(seed);
      }
      options.shading = flagOr(capture, "shading", "capture.shading", options.shading);
      options.noise_sigma = numberOr(capture, "noise_sigma", "capture.noise_sigma", options.noise_sigma);
      options.fisheye = flagOr(capture, "fisheye", "capture.fisheye", options.fisheye);
      options.low_texture_contrast =
          numberOr(capture, "low_texture_contrast", "capture.low_texture_contrast", options.low_texture_contrast);
      const YAML::Node flat = capture["low_texture_materials"];
      if (flat.IsDefined() && !flat.IsNull()) {
        if (!flat.IsSequence()) fail(flat, "capture.low_texture_materials", "must be a list of material names");
        options.low_texture_materials.clear();
        for (std::size_t i = 0; i < flat.size(); ++i) {
          options.low_texture_materials.push_back(text(flat[i], "capture.low_texture_materials[" + std::to_string(i) + "]"));
        }
      }
    });
  }

 private:
  static bool isKnown(const std::string& key) {
    for (const char* known : {"baseline_m", "width", "supersampling", "seed", "shading", "noise_sigma", "fisheye",
                              "low_texture_materials", "low_texture_contrast"}) {
      if (key == known) return true;
    }
    return false;
  }

  int wholeNumber(const YAML::Node& capture, const std::string& name, int fallback) const {
    const double value = numberOr(capture, name, "capture." + name, fallback);
    if (value != std::floor(value) || value < 0.0 || value > 1e6) fail(capture[name], "capture." + name, "must be a whole number");
    return static_cast<int>(value);
  }
};

std::string number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string vectorText(const Eigen::Vector3d& v) { return "[" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + "]"; }

// Names as plain YAML scalars when they are plain words, else double-quoted.
std::string nameText(const std::string& name) {
  bool plain = !name.empty() && name.front() != '-';
  for (const char c : name) plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.');
  if (plain && name != "null" && name != "true" && name != "false") return name;
  std::string out = "\"";
  for (const char c : name) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string nameList(const std::vector<std::string>& names) {
  std::string out = "[";
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + nameText(names[i]);
  return out + "]";
}

}  // namespace

CaptureScene parseCaptureScene(const std::string& yaml_text, const std::string& source) {
  CaptureScene scene;
  scene.room = parseRoomModel(yaml_text);
  CaptureSectionReader(source).read(yaml_text, scene.options);
  return scene;
}

CaptureScene loadCaptureScene(const std::string& path) {
  CaptureScene scene;
  scene.room = loadRoomModel(path);  // reports a missing file as "no such file"
  CaptureSectionReader(path).read(readTextFile(path, "capture scene"), scene.options);
  return scene;
}

std::string captureSceneToYaml(const CaptureScene& scene, const StereoCapture* rendered) {
  const CaptureOptions& o = scene.options;
  std::ostringstream out;
  out << roomModelToYaml(scene.room);
  out << "capture:  # how the synthetic capture is rendered (include/room_reverb/synthetic_capture/capture_scene.h)\n"
      << "  baseline_m: " << number(o.baseline_m) << "\n"
      << "  width: " << o.width << "\n"
      << "  supersampling: " << o.supersampling << "\n"
      << "  seed: " << o.seed << "\n"
      << "  shading: " << (o.shading ? "true" : "false") << "\n"
      << "  noise_sigma: " << number(o.noise_sigma) << "\n"
      << "  fisheye: " << (o.fisheye ? "true" : "false") << "\n"
      << "  low_texture_materials: " << nameList(o.low_texture_materials) << "\n"
      << "  low_texture_contrast: " << number(o.low_texture_contrast) << "\n";
  if (rendered != nullptr) {
    out << "labels:  # what the id images mean; 65535 is sky in both\n"
        << "  material_ids: " << nameList(rendered->material_names) << "  # *_material.png value i = i-th name\n"
        << "  object_ids: " << nameList(rendered->object_names) << "  # *_object.png value i = i-th name\n"
        << "  top_camera_m: " << vectorText(rendered->top.position_m) << "  # camera centres, room frame\n"
        << "  bottom_camera_m: " << vectorText(rendered->bottom.position_m) << "\n";
  }
  return out.str();
}

void saveCaptureScene(const std::string& path, const CaptureScene& scene, const StereoCapture* rendered) {
  writeTextFile(path, captureSceneToYaml(scene, rendered));
}

}  // namespace room_reverb::core
