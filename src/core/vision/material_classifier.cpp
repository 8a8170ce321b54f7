#include "room_reverb/vision/material_classifier.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/vision/material_features.h"

namespace room_reverb::core {
namespace {

constexpr const char* kFormat = "room_reverb_material_classifier";
constexpr int kVersion = 1;

void checkFeatureRows(const cv::Mat& features, const std::string& what) {
  if (features.empty() || features.type() != CV_32FC1 || features.cols != kMaterialFeatureLength) {
    throw InputError(what + ": expected rows of " + std::to_string(kMaterialFeatureLength) +
                     " CV_32F material features (materialFeatures), got " + std::to_string(features.rows) + " x " +
                     std::to_string(features.cols) + " of type " + std::to_string(features.type()));
  }
  if (!cv::checkRange(features)) throw InputError(what + ": a feature is not finite");
}

// Reads the file, turning OpenCV's parse errors (a corrupt file) into InputError.
cv::FileStorage openForReading(const std::string& path) {
  requireExistingFile(path, "material classifier", "train one with room_reverb train-materials");
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) throw InputError(path + ": cannot read the material classifier");
    return fs;
  } catch (const cv::Exception& e) {
    throw InputError(path + ": not a readable material classifier (" + e.msg + ")");
  }
}

}  // namespace

int textureFamilyIndex(TextureFamily family) {
  const std::vector<TextureFamily> all = allTextureFamilies();
  return static_cast<int>(std::find(all.begin(), all.end(), family) - all.begin());
}

TextureFamily textureFamilyAt(int index) { return allTextureFamilies().at(static_cast<std::size_t>(index)); }

MaterialClassifier MaterialClassifier::train(const cv::Mat& features, const std::vector<TextureFamily>& families,
                                             const MaterialPatchGeometry& geometry, const MaterialForestParams& params) {
  checkFeatureRows(features, "material classifier training");
  if (static_cast<std::size_t>(features.rows) != families.size()) {
    throw InputError("material classifier training: " + std::to_string(features.rows) + " feature rows but " +
                     std::to_string(families.size()) + " labels");
  }
  cv::Mat labels(features.rows, 1, CV_32SC1);
  std::vector<bool> present(kTextureFamilyCount, false);
  for (int i = 0; i < features.rows; ++i) {
    const int label = textureFamilyIndex(families[static_cast<std::size_t>(i)]);
    labels.at<int>(i) = label;
    present[static_cast<std::size_t>(label)] = true;
  }
  if (std::count(present.begin(), present.end(), true) < 2) {
    throw InputError("material classifier training: the samples show fewer than two families");
  }
  MaterialClassifier classifier;
  classifier.geometry_ = geometry;
  classifier.forest_ = cv::ml::RTrees::create();
  classifier.forest_->setMaxDepth(params.max_depth);
  classifier.forest_->setMinSampleCount(params.min_sample_count);
  classifier.forest_->setActiveVarCount(params.active_variables);
  classifier.forest_->setCalculateVarImportance(false);
  classifier.forest_->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER, params.trees, 0.0));
  classifier.forest_->train(cv::ml::TrainData::create(features, cv::ml::ROW_SAMPLE, labels));
  return classifier;
}

MaterialClassifier MaterialClassifier::load(const std::string& path) {
  cv::FileStorage fs = openForReading(path);
  MaterialClassifier classifier;
  try {
    if (static_cast<std::string>(fs["format"]) != kFormat) {
      throw InputError(path + ": not a material classifier (format is not " + std::string(kFormat) + ")");
    }
    const int version = static_cast<int>(fs["version"]);
    if (version != kVersion) throw InputError(path + ": material classifier version " + std::to_string(version) + " is not supported");
    const int length = static_cast<int>(fs["feature_length"]);
    if (length != kMaterialFeatureLength) {
      throw InputError(path + ": the classifier expects " + std::to_string(length) + " features but this build computes " +
                       std::to_string(kMaterialFeatureLength) + "; retrain it with room_reverb train-materials");
    }
    classifier.geometry_.size_m = static_cast<double>(fs["patch_size_m"]);
    classifier.geometry_.pixels = static_cast<int>(fs["patch_pixels"]);
    if (!(classifier.geometry_.size_m > 0.0) || classifier.geometry_.pixels < 8) {
      throw InputError(path + ": patch_size_m must be positive and patch_pixels at least 8");
    }
    classifier.forest_ = cv::ml::RTrees::create();
    const cv::FileNode model = fs["model"];
    if (model.empty()) throw InputError(path + ": no model in the material classifier");
    classifier.forest_->read(model);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": corrupt material classifier (" + e.msg + ")");
  }
  if (!classifier.forest_->isTrained() || classifier.forest_->getVarCount() != kMaterialFeatureLength) {
    throw InputError(path + ": the material classifier's model is empty or has the wrong number of inputs");
  }
  return classifier;
}

std::string MaterialClassifier::defaultPath() {
  return packageFilePath("ROOM_REVERB_MATERIAL_CLASSIFIER", "config/material_classifier.yml.gz");
}

void MaterialClassifier::save(const std::string& path, const std::string& description) const {
  if (!trained()) throw InputError(path + ": cannot save an untrained material classifier");
  try {
    cv::FileStorage fs(path, cv::FileStorage::WRITE);
    if (!fs.isOpened()) throw InputError(path + ": cannot write the material classifier");
    if (!description.empty()) fs.writeComment(description);
    fs << "format" << kFormat << "version" << kVersion << "feature_length" << kMaterialFeatureLength;
    fs << "patch_size_m" << geometry_.size_m << "patch_pixels" << geometry_.pixels;
    std::vector<std::string> names;
    for (const TextureFamily family : allTextureFamilies()) names.push_back(toString(family));
    fs << "families" << names;  // class label k is names[k]
    fs << "model" << "{";
    forest_->write(fs);
    fs << "}";
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot write the material classifier (" + e.msg + ")");
  }
}

std::vector<MaterialPrediction> MaterialClassifier::predictAll(const cv::Mat& features) const {
  checkFeatureRows(features, "material classifier");
  if (!trained()) throw InputError("material classifier: not trained");
  // getVotes: a header row of class labels, then one row of vote counts per sample.
  cv::Mat votes;
  forest_->getVotes(features, votes, 0);
  std::vector<MaterialPrediction> predictions(static_cast<std::size_t>(features.rows));
  for (int i = 0; i < features.rows; ++i) {
    MaterialPrediction& p = predictions[static_cast<std::size_t>(i)];
    double total = 0.0;
    for (int c = 0; c < votes.cols; ++c) {
      const int label = votes.at<int>(0, c);
      const double count = votes.at<int>(i + 1, c);
      if (label >= 0 && label < kTextureFamilyCount) p.posterior[static_cast<std::size_t>(label)] += count;
      total += count;
    }
    int best = 0;
    for (int k = 0; k < kTextureFamilyCount; ++k) {
      if (total > 0.0) p.posterior[static_cast<std::size_t>(k)] /= total;
      if (p.posterior[static_cast<std::size_t>(k)] > p.posterior[static_cast<std::size_t>(best)]) best = k;
    }
    p.family = textureFamilyAt(best);
    p.confidence = p.posterior[static_cast<std::size_t>(best)];
  }
  return predictions;
}

MaterialPrediction MaterialClassifier::predict(const cv::Mat& features) const {
  if (features.rows != 1) throw InputError("material classifier: predict takes one feature row, got " + std::to_string(features.rows));
  return predictAll(features).front();
}

}  // namespace room_reverb::core
