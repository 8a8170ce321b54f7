// The images' own noise, and where it drowns their texture (vision/texture_snr.h): the
// noise estimate against the sigma drawn, with and without shading and texture under it;
// the epipolar slope's signal-to-noise ratio against a texture of known slope energy.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <opencv2/core.hpp>

#include "texture_snr.h"

using namespace room_reverb::core::stereo_detail;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A 512 x 256 grey image: a smooth shading ramp, plus a sinusoid along the rows of slope
// amplitude `slope` [grey levels / px] and period 16 px, plus Gaussian noise, rounded to
// whole grey levels as an 8-bit camera writes them.
cv::Mat image(double noise_sigma, double slope, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_sigma);
  const double k = 2.0 * kPi / 16.0;
  cv::Mat grey(256, 512, CV_32FC1);
  for (int r = 0; r < grey.rows; ++r) {
    for (int c = 0; c < grey.cols; ++c) {
      const double level = 90.0 + 0.1 * r + 0.05 * c + (slope / k) * std::sin(k * c) + noise(rng);
      grey.at<float>(r, c) = static_cast<float>(std::round(std::clamp(level, 0.0, 255.0)));
    }
  }
  return grey;
}

EpipolarImage epipolar(const cv::Mat& grey) {
  cv::Mat grey8;
  grey.convertTo(grey8, CV_8U);
  return epipolarImage(grey8);
}

double mean(const cv::Mat& m) { return cv::mean(m(cv::Rect(16, 16, m.cols - 32, m.rows - 32)))[0]; }

}  // namespace

TEST(TextureSnr, NoiseEstimateMatchesTheSigmaDrawn) {
  for (const double sigma : {1.0, 2.0, 4.0, 6.0}) {
    EXPECT_NEAR(pixelNoiseSigma(image(sigma, 0.0, 1)), sigma, 0.06 * sigma) << "sigma " << sigma;
  }
  // A clean image reads the quantisation's floor, not zero.
  EXPECT_NEAR(pixelNoiseSigma(image(0.0, 0.0, 1)), 0.2887, 1e-3);
}

TEST(TextureSnr, NoiseEstimateMovesSmoothlyWithTheNoise) {
  // On 8-bit images the mask's response is a whole number; the estimate still follows a
  // noise between the quarter-level steps a plain median would snap to.
  const double a = pixelNoiseSigma(image(1.40, 0.0, 2)), b = pixelNoiseSigma(image(1.50, 0.0, 2));
  EXPECT_GT(b - a, 0.05);
  EXPECT_LT(b - a, 0.15);
}

TEST(TextureSnr, NoiseEstimateIgnoresAModerateTexture) {
  // A texture with slopes of 2 grey levels per pixel under noise of 2: the mask cancels
  // most of a smooth texture, and the median keeps the rest out.
  EXPECT_NEAR(pixelNoiseSigma(image(2.0, 2.0, 3)), 2.0, 0.25);
}

TEST(TextureSnr, PureNoiseHasNoTextureAndAKnownTextureItsRatio) {
  const double sigma = 3.0;
  const double noise_energy = 0.5 * sigma * sigma;  // the central difference's share of the noise
  // Noise alone: the ratio is 0 on average.
  EXPECT_NEAR(mean(epipolarTextureSnr(epipolar(image(sigma, 0.0, 4)), sigma, 7)), 0.0, 0.08);
  // A sinusoid of slope amplitude A has mean squared slope A^2 / 2, times the central
  // difference's response at its frequency, (sin(k) / k)^2 for k = 2 pi / 16.
  const double slope = 3.0, k = 2.0 * kPi / 16.0;
  const double expected = 0.5 * slope * slope * std::pow(std::sin(k) / k, 2) / noise_energy;
  EXPECT_NEAR(mean(epipolarTextureSnr(epipolar(image(sigma, slope, 5)), sigma, 7)), expected, 0.1 * expected);
}
