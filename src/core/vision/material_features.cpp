#include "room_reverb/vision/material_features.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "filter_bank_energy.h"
#include "local_binary_patterns.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

using namespace material_detail;

constexpr int kHueBins = 8;
constexpr int kColourBins = 1 + 2 * kHueBins;
constexpr int kContrastBins = 8;
constexpr double kContrastRange = 0.5;  // log(grey / mean) beyond +-0.5 goes to the end bins

// Offsets of the blocks in the vector (see the header).
constexpr int kBrightness = 0;
constexpr int kChroma = 1;
constexpr int kColour = 5;
constexpr int kContrast = kColour + kColourBins;
constexpr int kLogStd = kContrast + kContrastBins;
constexpr int kLbp = kLogStd + 1;
constexpr int kLbpRadii = 3;
constexpr int kFilters = kLbp + kLbpRadii * kLbpBins;
constexpr int kLineShare = kFilters + kFilterEnergies;
static_assert(kLineShare + 2 == kMaterialFeatureLength, "feature layout and length disagree");

void checkInputs(const cv::Mat& bgr, const cv::Mat& mask) {
  if (bgr.empty()) throw InputError("material features: the image is empty");
  if (bgr.type() != CV_8UC3) {
    throw InputError("material features: the image must be 8-bit BGR (CV_8UC3), got type " + std::to_string(bgr.type()));
  }
  if (mask.empty()) return;
  if (mask.type() != CV_8UC1) {
    throw InputError("material features: the mask must be 8-bit single-channel (CV_8UC1), got type " + std::to_string(mask.type()));
  }
  if (mask.size() != bgr.size()) {
    throw InputError("material features: the mask is " + std::to_string(mask.cols) + " x " + std::to_string(mask.rows) +
                     " but the image is " + std::to_string(bgr.cols) + " x " + std::to_string(bgr.rows));
  }
}

// Grey as the channel mean: every channel counts, so a saturated red and a grey of the
// same lightness give similar textures. Pixels outside the region get the region's mean,
// so neither the patterns nor the filters see whatever lies there, nor an edge at the
// region's border.
cv::Mat greyLevels(const cv::Mat& bgr, const cv::Mat& mask) {
  cv::Mat grey(bgr.size(), CV_32FC1);
  for (int y = 0; y < bgr.rows; ++y) {
    const unsigned char* in = bgr.ptr<unsigned char>(y);
    float* out = grey.ptr<float>(y);
    for (int x = 0; x < bgr.cols; ++x) out[x] = (in[3 * x] + in[3 * x + 1] + in[3 * x + 2]) / 3.0f;
  }
  grey.setTo(cv::mean(grey, mask), ~mask);
  return grey;
}

// Mean brightness, chromaticity moments and the hue-saturation histogram.
void colourFeatures(const cv::Mat& bgr, const cv::Mat& mask, double pixels, float* out) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV_FULL);  // hue over the full 0..255 range
  double grey = 0.0, r = 0.0, g = 0.0, rr = 0.0, gg = 0.0;
  float* colour = out + kColour;
  for (int y = 0; y < bgr.rows; ++y) {
    const unsigned char* m = mask.ptr<unsigned char>(y);
    const unsigned char* p = bgr.ptr<unsigned char>(y);
    const unsigned char* h = hsv.ptr<unsigned char>(y);
    for (int x = 0; x < bgr.cols; ++x) {
      if (!m[x]) continue;
      // +1 per channel: black pixels have a defined (neutral) chromaticity.
      const double b_ = p[3 * x] + 1.0, g_ = p[3 * x + 1] + 1.0, r_ = p[3 * x + 2] + 1.0;
      const double sum = b_ + g_ + r_;
      grey += (sum - 3.0) / 3.0;
      r += r_ / sum;
      g += g_ / sum;
      rr += (r_ / sum) * (r_ / sum);
      gg += (g_ / sum) * (g_ / sum);
      const double saturation = h[3 * x + 1] / 255.0;
      int bin = 0;
      if (saturation >= 0.1) {
        const int hue = std::min(kHueBins - 1, h[3 * x] * kHueBins / 256);
        bin = 1 + 2 * hue + (saturation >= 0.35 ? 1 : 0);
      }
      colour[bin] += 1.0f;
    }
  }
  for (int b = 0; b < kColourBins; ++b) colour[b] = static_cast<float>(colour[b] / pixels);
  r /= pixels;
  g /= pixels;
  out[kBrightness] = static_cast<float>(grey / pixels / 255.0);
  out[kChroma] = static_cast<float>(r);
  out[kChroma + 1] = static_cast<float>(g);
  out[kChroma + 2] = static_cast<float>(std::sqrt(std::max(0.0, rr / pixels - r * r)));
  out[kChroma + 3] = static_cast<float>(std::sqrt(std::max(0.0, gg / pixels - g * g)));
}

// Histogram and spread of log(grey / mean): the texture's contrast, free of the gain.
void contrastFeatures(const cv::Mat& log_grey, const cv::Mat& mask, double pixels, float* out) {
  const double mean = cv::mean(log_grey, mask)[0];
  double variance = 0.0;
  for (int y = 0; y < log_grey.rows; ++y) {
    const unsigned char* m = mask.ptr<unsigned char>(y);
    const float* l = log_grey.ptr<float>(y);
    for (int x = 0; x < log_grey.cols; ++x) {
      if (!m[x]) continue;
      const double d = l[x] - mean;
      variance += d * d;
      const double position = (d + kContrastRange) / (2.0 * kContrastRange) * kContrastBins;
      const int bin = std::clamp(static_cast<int>(std::floor(position)), 0, kContrastBins - 1);
      out[kContrast + bin] += 1.0f;
    }
  }
  for (int b = 0; b < kContrastBins; ++b) out[kContrast + b] = static_cast<float>(out[kContrast + b] / pixels);
  out[kLogStd] = static_cast<float>(std::sqrt(variance / pixels));
}

// Share of the region's log-grey variance held by its row means and by its column means
// (each mean over the region's pixels of that row or column), larger first.
void lineShareFeatures(const cv::Mat& log_grey, const cv::Mat& mask, float* out) {
  cv::Scalar mean, deviation;
  cv::meanStdDev(log_grey, mean, deviation, mask);
  const double variance = deviation[0] * deviation[0];
  std::vector<double> row_sum(static_cast<std::size_t>(log_grey.rows), 0.0), col_sum(static_cast<std::size_t>(log_grey.cols), 0.0);
  std::vector<int> row_n(row_sum.size(), 0), col_n(col_sum.size(), 0);
  for (int y = 0; y < log_grey.rows; ++y) {
    const unsigned char* m = mask.ptr<unsigned char>(y);
    const float* l = log_grey.ptr<float>(y);
    for (int x = 0; x < log_grey.cols; ++x) {
      if (!m[x]) continue;
      const double d = l[x] - mean[0];
      row_sum[static_cast<std::size_t>(y)] += d;
      col_sum[static_cast<std::size_t>(x)] += d;
      ++row_n[static_cast<std::size_t>(y)];
      ++col_n[static_cast<std::size_t>(x)];
    }
  }
  // Variance of the line means, each line weighted by its pixels (a pixel-weighted
  // decomposition: the between-lines part of the total variance).
  auto between = [](const std::vector<double>& sum, const std::vector<int>& n) {
    double energy = 0.0, pixels = 0.0;
    for (std::size_t i = 0; i < sum.size(); ++i) {
      if (n[i] == 0) continue;
      energy += sum[i] * sum[i] / n[i];
      pixels += n[i];
    }
    return pixels > 0.0 ? energy / pixels : 0.0;
  };
  const double rows = variance > 1e-12 ? between(row_sum, row_n) / variance : 0.0;
  const double cols = variance > 1e-12 ? between(col_sum, col_n) / variance : 0.0;
  out[kLineShare] = static_cast<float>(std::max(rows, cols));
  out[kLineShare + 1] = static_cast<float>(std::min(rows, cols));
}

}  // namespace

cv::Mat materialFeatures(const cv::Mat& bgr, const cv::Mat& mask_in) {
  checkInputs(bgr, mask_in);
  const cv::Mat mask = mask_in.empty() ? cv::Mat(bgr.size(), CV_8UC1, cv::Scalar(255)) : mask_in;
  const int pixels = cv::countNonZero(mask);
  if (pixels < kMinMaterialRegionPixels) {
    throw InputError("material features: the region has " + std::to_string(pixels) + " pixels, fewer than the " +
                     std::to_string(kMinMaterialRegionPixels) + " needed");
  }
  cv::Mat features = cv::Mat::zeros(1, kMaterialFeatureLength, CV_32F);
  float* out = features.ptr<float>(0);
  colourFeatures(bgr, mask, pixels, out);

  const cv::Mat grey = greyLevels(bgr, mask);
  cv::Mat log_grey;
  // +4 grey levels: keeps log finite on black and stops the noise of near-black pixels
  // from dominating the ratios.
  cv::log(grey + 4.0f, log_grey);
  contrastFeatures(log_grey, mask, pixels, out);
  const double radii[kLbpRadii] = {1.0, 2.0, 4.0};
  for (int k = 0; k < kLbpRadii; ++k) lbpHistogram(grey, mask, radii[k], out + kLbp + k * kLbpBins);
  filterBankEnergies(log_grey, mask, out + kFilters);
  lineShareFeatures(log_grey, mask, out);
  return features;
}

}  // namespace room_reverb::core
