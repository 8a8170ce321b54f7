#include "room_reverb/synthetic_capture/capture_scene.h"

#include <algorithm>
#include <cctype>
#include <iterator>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/yaml_reader.h"

namespace room_reverb::core {
namespace {

class CaptureSectionReader : public YamlReader {
 public:
  using YamlReader::YamlReader;

  void read(const std::string& yaml_text, CaptureScene& scene) const {
    CaptureOptions& options = scene.options;
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
               "low_texture_materials, low_texture_contrast, photo_textures, photo_sources, photo_share, camera)");
        }
      }
      options.baseline_m = numberOr(capture, "baseline_m", "capture.baseline_m", options.baseline_m);
      options.width = wholeNumber(capture, "capture.", "width", options.width);
      options.supersampling = wholeNumber(capture, "capture.", "supersampling", options.supersampling);
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
      readNames(capture["low_texture_materials"], "capture.low_texture_materials", "material names", options.low_texture_materials);
      if (capture["photo_textures"].IsDefined() && !capture["photo_textures"].IsNull()) {
        scene.photo_textures = text(capture["photo_textures"], "capture.photo_textures");
      }
      const YAML::Node sources = capture["photo_sources"];
      readNames(sources, "capture.photo_sources", "collection names", scene.photo_sources);
      if (sources.IsDefined() && !sources.IsNull() && scene.photo_textures.empty()) {
        fail(sources, "capture.photo_sources", "needs photo_textures");
      }
      options.photo_share = numberOr(capture, "photo_share", "capture.photo_share", options.photo_share);
      const YAML::Node camera = capture["camera"];
      if (camera.IsDefined() && !camera.IsNull()) readCamera(camera, options.camera);
    });
  }

 private:
  static bool isKnown(const std::string& key) {
    for (const char* known : {"baseline_m", "width", "supersampling", "seed", "shading", "noise_sigma", "fisheye",
                              "low_texture_materials", "low_texture_contrast", "photo_textures", "photo_sources",
                              "photo_share", "camera"}) {
      if (key == known) return true;
    }
    return false;
  }

  void readCamera(const YAML::Node& node, CameraImperfections& c) const {
    requireMap(node, "capture.camera");
    static const char* const kKeys[] = {"through_lenses", "lens_offset_m", "vignetting", "back_lens_gain", "top_exposure",
                                        "bottom_exposure", "bottom_white_balance", "jpeg_quality", "native_scale", "emitter_labels",
                                        "emitter_grey", "top_turn_deg", "bottom_turn_deg"};
    for (const auto& entry : node) {
      const std::string key = entry.first.as<std::string>();
      if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys)) {
        fail(entry.first, "capture.camera." + key,
             "unknown key (use through_lenses, lens_offset_m, vignetting, back_lens_gain, top_exposure, bottom_exposure, "
             "bottom_white_balance, jpeg_quality, native_scale, emitter_labels, emitter_grey, top_turn_deg, "
             "bottom_turn_deg)");
      }
    }
    c.through_lenses = flagOr(node, "through_lenses", "capture.camera.through_lenses", c.through_lenses);
    c.lens_offset_m = numberOr(node, "lens_offset_m", "capture.camera.lens_offset_m", c.lens_offset_m);
    c.vignetting = numberOr(node, "vignetting", "capture.camera.vignetting", c.vignetting);
    c.back_lens_gain = numberOr(node, "back_lens_gain", "capture.camera.back_lens_gain", c.back_lens_gain);
    c.top_exposure = numberOr(node, "top_exposure", "capture.camera.top_exposure", c.top_exposure);
    c.bottom_exposure = numberOr(node, "bottom_exposure", "capture.camera.bottom_exposure", c.bottom_exposure);
    if (node["bottom_white_balance"].IsDefined()) {
      c.bottom_white_balance = vector3(node["bottom_white_balance"], "capture.camera.bottom_white_balance");
    }
    // Their ranges are validateCapture's to check, as for every other key.
    c.jpeg_quality = wholeNumber(node, "capture.camera.", "jpeg_quality", c.jpeg_quality);
    c.native_scale = wholeNumber(node, "capture.camera.", "native_scale", c.native_scale);
    readNames(node["emitter_labels"], "capture.camera.emitter_labels", "object labels", c.emitter_labels);
    c.emitter_grey = numberOr(node, "emitter_grey", "capture.camera.emitter_grey", c.emitter_grey);
    if (node["top_turn_deg"].IsDefined()) c.top_turn_deg = vector3(node["top_turn_deg"], "capture.camera.top_turn_deg");
    if (node["bottom_turn_deg"].IsDefined()) {
      c.bottom_turn_deg = vector3(node["bottom_turn_deg"], "capture.camera.bottom_turn_deg");
    }
  }

  // `parent[name]` (its key `prefix` + name in messages), a whole number 0..10^6.
  int wholeNumber(const YAML::Node& parent, const std::string& prefix, const std::string& name, int fallback) const {
    const double value = numberOr(parent, name, prefix + name, fallback);
    if (value != std::floor(value) || value < 0.0 || value > 1e6) fail(parent[name], prefix + name, "must be a whole number");
    return static_cast<int>(value);
  }

  // A list of names at `key`, replacing `out` when given; `what` says what they name.
  void readNames(const YAML::Node& list, const std::string& key, const std::string& what, std::vector<std::string>& out) const {
    if (!list.IsDefined() || list.IsNull()) return;
    if (!list.IsSequence()) fail(list, key, "must be a list of " + what);
    out.clear();
    for (std::size_t i = 0; i < list.size(); ++i) out.push_back(text(list[i], key + "[" + std::to_string(i) + "]"));
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

// The photographs the scene names, relative paths from `folder`.
void loadScenePhotos(CaptureScene& scene, const std::string& source, const std::filesystem::path& folder) {
  if (scene.photo_textures.empty()) return;
  std::string path = scene.photo_textures;
  if (path == "default") {
    path = defaultPhotoTexturePath();
  } else if (std::filesystem::path(path).is_relative()) {
    // Kept resolved, so that a scene written elsewhere (make-capture's output) still finds it.
    path = std::filesystem::absolute(folder / path).lexically_normal().string();
    scene.photo_textures = path;
  }
  PhotoTextureSet set = loadPhotoTextures(path);
  if (!scene.photo_sources.empty()) {
    try {
      set = set.onlySources(scene.photo_sources);
    } catch (const InputError& e) {
      throw InputError(source + ": capture.photo_sources: " + e.what());
    }
  }
  scene.options.photo_textures = std::make_shared<const PhotoTextureSet>(std::move(set));
}

CaptureScene parseCaptureScene(const std::string& yaml_text, const std::string& source) {
  CaptureScene scene;
  scene.room = parseRoomModel(yaml_text);
  CaptureSectionReader(source).read(yaml_text, scene);
  loadScenePhotos(scene, source, std::filesystem::current_path());
  return scene;
}

CaptureScene loadCaptureScene(const std::string& path) {
  CaptureScene scene;
  scene.room = loadRoomModel(path);  // reports a missing file as "no such file"
  CaptureSectionReader(path).read(readTextFile(path, "capture scene"), scene);
  loadScenePhotos(scene, path, std::filesystem::path(path).parent_path());
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
  const CameraImperfections& c = o.camera;
  const CameraImperfections ideal;
  const bool imperfect = c.through_lenses || c.lens_offset_m != ideal.lens_offset_m || c.vignetting != ideal.vignetting ||
                         c.back_lens_gain != ideal.back_lens_gain || c.top_exposure != ideal.top_exposure ||
                         c.bottom_exposure != ideal.bottom_exposure || c.bottom_white_balance != ideal.bottom_white_balance ||
                         c.jpeg_quality != ideal.jpeg_quality || c.native_scale != ideal.native_scale ||
                         !c.emitter_labels.empty() || c.top_turn_deg != ideal.top_turn_deg ||
                         c.bottom_turn_deg != ideal.bottom_turn_deg;
  if (imperfect) {
    out << "  camera:  # what the camera does to the light (CameraImperfections)\n"
        << "    through_lenses: " << (c.through_lenses ? "true" : "false") << "\n"
        << "    lens_offset_m: " << number(c.lens_offset_m) << "\n"
        << "    vignetting: " << number(c.vignetting) << "\n"
        << "    back_lens_gain: " << number(c.back_lens_gain) << "\n"
        << "    top_exposure: " << number(c.top_exposure) << "\n"
        << "    bottom_exposure: " << number(c.bottom_exposure) << "\n"
        << "    bottom_white_balance: " << vectorText(c.bottom_white_balance) << "\n"
        << "    jpeg_quality: " << c.jpeg_quality << "\n"
        << "    native_scale: " << c.native_scale << "\n"
        << "    emitter_labels: " << nameList(c.emitter_labels) << "\n"
        << "    emitter_grey: " << number(c.emitter_grey) << "\n"
        << "    top_turn_deg: " << vectorText(c.top_turn_deg) << "\n"
        << "    bottom_turn_deg: " << vectorText(c.bottom_turn_deg) << "\n";
  }
  if (!scene.photo_textures.empty()) {
    out << "  photo_textures: " << nameText(scene.photo_textures) << "\n"
        << "  photo_sources: " << nameList(scene.photo_sources) << "\n"
        << "  photo_share: " << number(o.photo_share) << "\n";
  }
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
