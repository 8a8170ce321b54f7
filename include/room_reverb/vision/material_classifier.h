#pragma once
// A surface-material classifier on colour and texture features (vision/material_features.h):
// an OpenCV random forest whose classes are the texture families (vision/texture_family.h).
// Trained by synthetic_capture/material_training.h on the capture generator's textures; the project
// ships one in config/material_classifier.yml.gz (see its header comment).
//
// A random forest was chosen over an RBF SVM and a small MLP by held-out accuracy on
// generated patches (600 per family for training, rooms of other seeds for testing: forest
// 96.8 %, SVM with grid-searched C and gamma 93.5 %, MLP 85-64-12 82.5 %); it also trains in
// seconds, needs no feature scaling, and its vote shares give a posterior-like confidence.
#include <array>
#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>
#include <string>

#include "room_reverb/vision/texture_family.h"

namespace room_reverb::core {

constexpr int kTextureFamilyCount = 12;  // allTextureFamilies().size()

// The patches a classifier was trained on: squares of size_m x size_m of a surface seen
// face-on, resampled to pixels x pixels. Classifying other patches would change the
// texture scale the features measure, so the classifier file carries these.
struct MaterialPatchGeometry {
  double size_m = 0.6;
  int pixels = 48;
};

struct MaterialPrediction {
  TextureFamily family = TextureFamily::kPlaster;
  double confidence = 0.0;  // the family's share of the forest's votes, in [0, 1]
  // Vote share of every family, in allTextureFamilies() order (sums to 1).
  std::array<double, kTextureFamilyCount> posterior{};
};

// Chosen on the held-out set: deeper or more trees gained nothing measurable but size (the
// shipped file stays under 2 MB).
struct MaterialForestParams {
  int trees = 80;
  int max_depth = 20;
  int min_sample_count = 3;
  int active_variables = 0;  // features tried per split; 0: sqrt of the feature count
};

class MaterialClassifier {
 public:
  // `features`: N x kMaterialFeatureLength CV_32F; `families`: N labels. InputError for
  // mismatched sizes, fewer than two families or a non-finite feature.
  static MaterialClassifier train(const cv::Mat& features, const std::vector<TextureFamily>& families,
                                  const MaterialPatchGeometry& geometry, const MaterialForestParams& params = {});

  // cv::FileStorage YAML (".yml", or gzip-compressed ".yml.gz"). InputError for a missing,
  // unreadable or corrupt file, another format, or a feature length other than this
  // build's kMaterialFeatureLength (a model from another version of the features).
  static MaterialClassifier load(const std::string& path);
  // config/material_classifier.yml.gz of the package, or $ROOM_REVERB_MATERIAL_CLASSIFIER.
  static std::string defaultPath();
  // `description`: a comment written at the top of the file (what it is, how it was made).
  void save(const std::string& path, const std::string& description = "") const;

  // `features`: one 1 x kMaterialFeatureLength CV_32F row (InputError otherwise).
  MaterialPrediction predict(const cv::Mat& features) const;
  // One prediction per row of an N x kMaterialFeatureLength matrix.
  std::vector<MaterialPrediction> predictAll(const cv::Mat& features) const;

  const MaterialPatchGeometry& patchGeometry() const { return geometry_; }
  bool trained() const { return forest_ && forest_->isTrained(); }

 private:
  cv::Ptr<cv::ml::RTrees> forest_;
  MaterialPatchGeometry geometry_;
};

// Index of a family in allTextureFamilies() (the classifier's class label), and back.
int textureFamilyIndex(TextureFamily family);
TextureFamily textureFamilyAt(int index);

}  // namespace room_reverb::core
