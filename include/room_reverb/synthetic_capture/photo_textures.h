#pragma once
// Photographs of real surfaces for the synthetic captures. The procedural textures
// (procedural_texture.h) are the generator's own drawings; a classifier that has only seen
// them learns the generator's palette (blue-grey carpet, red fabric) rather than what a
// material looks like. A capture can instead paint a material with a photograph of its
// family, tiled over the surface at the photograph's physical size.
//
// The set is a CSV (data/textures/textures.csv) with one row per photograph:
//   file,family,width_m,source,licence,origin
// `file` relative to the CSV's folder (JPEG or PNG), `family` a texture family name
// (texture_family.h), `width_m` the width of surface the image shows [m], `source` the
// collection it comes from (the unit of cross-source evaluation: a classifier is tested
// on photographs from a collection it was not trained on), `licence` and `origin` for
// the record. data/README.md lists the collections and their licences.
#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "room_reverb/vision/texture_family.h"

namespace room_reverb::core {

struct PhotoTexture {
  std::string file;  // as written in the CSV
  TextureFamily family = TextureFamily::kPlaster;
  double width_m = 1.0;
  std::string source;
  std::string licence;
  // RGB grey levels as CV_32FC3; levels[0] is the photograph, each next level half the
  // size of the one before (box-filtered), down to a few pixels: sampling picks the level
  // whose pixel matches the footprint on the surface, so far surfaces are not aliased.
  std::vector<cv::Mat> levels;
  Eigen::Array3d mean_rgb = Eigen::Array3d::Zero();
};

struct PhotoTextureSet {
  std::vector<std::shared_ptr<const PhotoTexture>> textures;

  bool empty() const { return textures.empty(); }
  // The collections present, sorted, each once.
  std::vector<std::string> sources() const;
  std::vector<std::shared_ptr<const PhotoTexture>> ofFamily(TextureFamily family) const;
  bool hasFamily(TextureFamily family) const { return !ofFamily(family).empty(); }
  // The photographs of the named collections only, or of all others. InputError for a
  // name that is not a collection of the set.
  PhotoTextureSet onlySources(const std::vector<std::string>& names) const;
  PhotoTextureSet withoutSources(const std::vector<std::string>& names) const;
};

// Reads the CSV and every image it names. InputError (one line, naming the file and row)
// for a missing or unreadable CSV or image, a wrong header, a row without six fields, an
// unknown family, or a width that is not a positive number.
PhotoTextureSet loadPhotoTextures(const std::string& csv_path);

// data/textures/textures.csv of the package, or $ROOM_REVERB_PHOTO_TEXTURES.
std::string defaultPhotoTexturePath();

// The colour (RGB grey levels) at (s_m, t_m) on a surface tiled with `texture` at
// `width_m` per image width (its own width_m, or a scaled one), filtered to `footprint_m`.
Eigen::Array3d photoTextureColor(const PhotoTexture& texture, double width_m, double s_m, double t_m,
                                 double footprint_m);

}  // namespace room_reverb::core
