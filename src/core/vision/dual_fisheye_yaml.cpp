// config/dual_fisheye.yaml: reading and writing the dual-fisheye calibration.
#include <charconv>
#include <cmath>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/yaml_reader.h"
#include "room_reverb/vision/dual_fisheye.h"

namespace room_reverb::core {
namespace {

class CalibrationReader : public YamlReader {
 public:
  using YamlReader::YamlReader;

  DualFisheyeCalibration parse(const std::string& yaml_text) const {
    return guarded("dual-fisheye calibration", [&] {
      const YAML::Node root = loadMap(yaml_text, "a dual-fisheye calibration with size_px, front and back");
      const double size = numberOr(root, "size_px", "size_px", 1024.0);
      if (size != std::floor(size) || size < 16.0 || size > 1e6) {
        fail(root["size_px"], "size_px", "must be a whole number of pixels, at least 16");
      }
      // Missing lens keys take the ideal lens's values for this size.
      DualFisheyeCalibration calibration = idealDualFisheye(static_cast<int>(size));
      readLens(root, "front", calibration.front);
      readLens(root, "back", calibration.back);
      validateDualFisheyeCalibration(calibration, source());
      return calibration;
    });
  }

 private:
  void readLens(const YAML::Node& root, const std::string& name, FisheyeLens& lens) const {
    const YAML::Node node = root[name];
    if (!node.IsDefined() || node.IsNull()) return;
    requireMap(node, name);
    if (node["center_px"].IsDefined()) {
      const auto c = numbers(node["center_px"], name + ".center_px", 2);
      lens.center_px = Eigen::Vector2d(c[0], c[1]);
    }
    lens.radius_px = numberOr(node, "radius_px", name + ".radius_px", lens.radius_px);
    lens.fov_deg = numberOr(node, "fov_deg", name + ".fov_deg", lens.fov_deg);
    if (node["rotation_rpy_deg"].IsDefined()) lens.rotation_rpy_deg = vector3(node["rotation_rpy_deg"], name + ".rotation_rpy_deg");
  }
};

// Shortest decimals that read back exactly.
std::string number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

void writeLens(std::ostream& out, const std::string& name, const std::string& what, const FisheyeLens& lens) {
  out << name << ":  # " << what << "\n"
      << "  center_px: [" << number(lens.center_px.x()) << ", " << number(lens.center_px.y())
      << "]  # principal point (cx, cy) in this lens's half [px]; default [S/2, S/2]\n"
      << "  radius_px: " << number(lens.radius_px) << "  # image circle radius, where the fov/2 ray lands [px]; default 0.48 S\n"
      << "  fov_deg: " << number(lens.fov_deg) << "  # full field of view of the image circle [deg]; default 190\n"
      << "  rotation_rpy_deg: [" << number(lens.rotation_rpy_deg.x()) << ", " << number(lens.rotation_rpy_deg.y()) << ", "
      << number(lens.rotation_rpy_deg.z())
      << "]  # roll, pitch, yaw of the lens off its nominal mount, about camera x, y, z [deg]; default [0, 0, 0]\n";
}

}  // namespace

DualFisheyeCalibration parseDualFisheyeCalibration(const std::string& yaml_text, const std::string& source) {
  return CalibrationReader(source).parse(yaml_text);
}

DualFisheyeCalibration loadDualFisheyeCalibration(const std::string& path) {
  return CalibrationReader(path).parse(readTextFile(path, "dual-fisheye calibration (config/dual_fisheye.yaml format)"));
}

std::string dualFisheyeCalibrationToYaml(const DualFisheyeCalibration& calibration) {
  validateDualFisheyeCalibration(calibration, "dual-fisheye calibration");
  std::ostringstream out;
  out << "# room_reverb dual-fisheye calibration (include/room_reverb/vision/dual_fisheye.h): equidistant lenses,\n"
      << "# image 2S x S with the front lens in the left half; pixel (i, j) covers [i, i+1) x [j, j+1)\n"
      << "size_px: " << calibration.size_px << "  # S: each lens's half is S x S [px]; default 1024\n";
  writeLens(out, "front", "left half, looks along the camera's +x, image right = -y", calibration.front);
  writeLens(out, "back", "right half, looks along the camera's -x, image right = +y", calibration.back);
  return out.str();
}

void saveDualFisheyeCalibration(const std::string& path, const DualFisheyeCalibration& calibration) {
  writeTextFile(path, dualFisheyeCalibrationToYaml(calibration));
}

std::string defaultDualFisheyeCalibrationPath() {
  return packageFilePath("ROOM_REVERB_DUAL_FISHEYE", "config/dual_fisheye.yaml");
}

}  // namespace room_reverb::core
