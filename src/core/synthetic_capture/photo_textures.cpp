#include "room_reverb/synthetic_capture/photo_textures.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/vision/material_families.h"

namespace room_reverb::core {
namespace {

constexpr const char* kHeader = "file,family,width_m,source,licence,origin";
constexpr int kSmallestLevel = 4;  // pixels: below this a level is one flat colour anyway

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::vector<cv::Mat> mipLevels(const cv::Mat& bgr) {
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  std::vector<cv::Mat> levels(1);
  rgb.convertTo(levels[0], CV_32FC3);
  while (std::min(levels.back().cols, levels.back().rows) >= 2 * kSmallestLevel) {
    cv::Mat next;
    cv::resize(levels.back(), next, cv::Size(levels.back().cols / 2, levels.back().rows / 2), 0, 0, cv::INTER_AREA);
    levels.push_back(next);
  }
  return levels;
}

PhotoTextureSet filtered(const PhotoTextureSet& set, const std::vector<std::string>& names, bool keep) {
  const std::vector<std::string> present = set.sources();
  for (const std::string& name : names) {
    if (std::find(present.begin(), present.end(), name) == present.end()) {
      std::string known;
      for (const std::string& p : present) known += (known.empty() ? "" : ", ") + p;
      throw InputError("photo textures: no collection named '" + name + "' (the set has " + known + ")");
    }
  }
  PhotoTextureSet out;
  for (const auto& texture : set.textures) {
    const bool named = std::find(names.begin(), names.end(), texture->source) != names.end();
    if (named == keep) out.textures.push_back(texture);
  }
  return out;
}

// Bilinear, wrapping in both directions (the photograph tiles the surface).
Eigen::Array3d sampleWrapped(const cv::Mat& level, double x, double y) {
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy;
  auto wrap = [](long v, int n) { return static_cast<int>(((v % n) + n) % n); };
  const int x0 = wrap(static_cast<long>(fx), level.cols), x1 = wrap(static_cast<long>(fx) + 1, level.cols);
  const int y0 = wrap(static_cast<long>(fy), level.rows), y1 = wrap(static_cast<long>(fy) + 1, level.rows);
  auto at = [&](int yy, int xx) {
    const cv::Vec3f& p = level.at<cv::Vec3f>(yy, xx);
    return Eigen::Array3d(p[0], p[1], p[2]);
  };
  return (1 - ay) * ((1 - ax) * at(y0, x0) + ax * at(y0, x1)) + ay * ((1 - ax) * at(y1, x0) + ax * at(y1, x1));
}

}  // namespace

std::vector<std::string> PhotoTextureSet::sources() const {
  std::set<std::string> names;
  for (const auto& texture : textures) names.insert(texture->source);
  return {names.begin(), names.end()};
}

std::vector<std::shared_ptr<const PhotoTexture>> PhotoTextureSet::ofFamily(TextureFamily family) const {
  std::vector<std::shared_ptr<const PhotoTexture>> out;
  for (const auto& texture : textures) {
    if (texture->family == family) out.push_back(texture);
  }
  return out;
}

PhotoTextureSet PhotoTextureSet::onlySources(const std::vector<std::string>& names) const { return filtered(*this, names, true); }

PhotoTextureSet PhotoTextureSet::withoutSources(const std::vector<std::string>& names) const {
  return filtered(*this, names, false);
}

PhotoTextureSet loadPhotoTextures(const std::string& csv_path) {
  const std::string text = readTextFile(csv_path, "photo texture list (CSV)");
  const std::filesystem::path folder = std::filesystem::path(csv_path).parent_path();
  std::stringstream lines(text);
  std::string line;
  int row = 0;
  PhotoTextureSet set;
  while (std::getline(lines, line)) {
    ++row;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = csv_path + " line " + std::to_string(row);
    if (row == 1) {
      if (line != kHeader) throw InputError(where + ": the header must be '" + std::string(kHeader) + "'");
      continue;
    }
    if (line.empty()) continue;
    const std::vector<std::string> fields = splitFields(line);
    if (fields.size() != 6) {
      throw InputError(where + ": expected 6 fields (" + std::string(kHeader) + "), got " + std::to_string(fields.size()));
    }
    auto texture = std::make_shared<PhotoTexture>();
    texture->file = fields[0];
    texture->family = textureFamilyNamed(fields[1], where);
    std::size_t used = 0;
    double width = 0.0;
    try {
      width = std::stod(fields[2], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != fields[2].size() || !(width > 0.0) || !std::isfinite(width)) {
      throw InputError(where + ": width_m '" + fields[2] + "' is not a positive number of metres");
    }
    texture->width_m = width;
    texture->source = fields[3];
    texture->licence = fields[4];
    if (texture->source.empty()) throw InputError(where + ": the source (collection) is empty");
    const std::string image_path = (folder / fields[0]).string();
    requireExistingFile(image_path, "texture photograph", "listed at " + where);
    const cv::Mat image = cv::imread(image_path, cv::IMREAD_COLOR);
    if (image.empty() || image.cols < kSmallestLevel || image.rows < kSmallestLevel) {
      throw InputError(image_path + ": not a readable image of at least " + std::to_string(kSmallestLevel) + " x " +
                       std::to_string(kSmallestLevel) + " pixels (listed at " + where + ")");
    }
    texture->levels = mipLevels(image);
    const cv::Scalar mean = cv::mean(texture->levels[0]);
    texture->mean_rgb = Eigen::Array3d(mean[0], mean[1], mean[2]);
    set.textures.push_back(std::move(texture));
  }
  if (row == 0) throw InputError(csv_path + ": empty; the header must be '" + std::string(kHeader) + "'");
  return set;
}

std::string defaultPhotoTexturePath() { return packageFilePath("ROOM_REVERB_PHOTO_TEXTURES", "data/textures/textures.csv"); }

Eigen::Array3d photoTextureColor(const PhotoTexture& texture, double width_m, double s_m, double t_m,
                                 double footprint_m) {
  const double pixel_m = width_m / texture.levels[0].cols;
  // The level whose pixel is about the footprint: finer levels would alias.
  const double ratio = footprint_m > pixel_m ? footprint_m / pixel_m : 1.0;
  const int level = std::clamp(static_cast<int>(std::floor(std::log2(ratio))), 0, static_cast<int>(texture.levels.size()) - 1);
  const cv::Mat& image = texture.levels[static_cast<std::size_t>(level)];
  const double scale = static_cast<double>(image.cols) / width_m;  // pixels per metre at this level
  // Pixel centres at half-integers; t grows upwards on walls, rows grow downwards.
  return sampleWrapped(image, s_m * scale - 0.5, -t_m * scale - 0.5);
}

}  // namespace room_reverb::core
