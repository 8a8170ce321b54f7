#include "room_reverb/vision/tile_joints.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace room_reverb::core::material_detail {
namespace {

// A position of a profile counts where at least this many pixel pairs across it are seen.
constexpr int kMinPairs = 8;
// The slow change of the profile (sharper near the camera, blurred far away) is taken out
// by a running mean this many periods of the longest kind wide.
constexpr double kTrendWindowPeriods = 2.0;
// The shortest peak of the autocorrelation within this share of its highest is the period.
constexpr double kFundamentalShare = 0.8;

struct Profile {
  std::vector<double> value;  // mean |gradient| across the axis, per position along it
  std::vector<char> valid;
};

// The joint profile along the mosaic's columns (`along_columns`) or rows: the mean of the
// patches' normalised gradients across that axis (jointGridOfFace), over the pixels that
// have one.
Profile jointProfile(const cv::Mat& gradient, const cv::Mat& has, bool along_columns) {
  const int length = along_columns ? gradient.cols : gradient.rows;
  const int across = along_columns ? gradient.rows : gradient.cols;
  Profile p{std::vector<double>(static_cast<std::size_t>(length), 0.0), std::vector<char>(static_cast<std::size_t>(length), 0)};
  for (int i = 0; i < length; ++i) {
    double sum = 0.0;
    int pairs = 0;
    for (int k = 0; k < across; ++k) {
      const int r = along_columns ? k : i, c = along_columns ? i : k;
      if (!has.at<std::uint8_t>(r, c)) continue;
      sum += gradient.at<float>(r, c);
      ++pairs;
    }
    if (pairs >= kMinPairs) {
      p.value[static_cast<std::size_t>(i)] = sum / pairs;
      p.valid[static_cast<std::size_t>(i)] = 1;
    }
  }
  // A joint's edges fall on one pixel or two depending on where it lies against the
  // pixel grid: a [1 2 1] smoothing gives every joint the same profile.
  std::vector<double> smooth(p.value.size(), 0.0);
  for (int i = 0; i < length; ++i) {
    if (!p.valid[static_cast<std::size_t>(i)]) continue;
    double sum = 2.0 * p.value[static_cast<std::size_t>(i)], weight = 2.0;
    for (const int k : {i - 1, i + 1}) {
      if (k >= 0 && k < length && p.valid[static_cast<std::size_t>(k)]) sum += p.value[static_cast<std::size_t>(k)], weight += 1.0;
    }
    smooth[static_cast<std::size_t>(i)] = sum / weight;
  }
  p.value = smooth;
  return p;
}

// One patch's absolute central differences of log grey along its columns (`along_columns`)
// or rows, where both neighbours are seen, divided by their mean: each patch is read from
// the image level that suits its range (surface_patches.h), so patches differ in
// sharpness, and without the division the mosaic's profiles would repeat at the patch
// size. Pairs never straddle two patches, whose levels and shading differ, so a joint
// that falls on a patch's edge is missed: where the tiles' period divides the patch size
// and their joints line up with the patches' edges, every other joint is missed and the
// period reads twice as long (still a grid).
void patchGradient(const cv::Mat& grey, const cv::Mat& mask, bool along_columns, cv::Mat& gradient, cv::Mat& has) {
  gradient = cv::Mat(grey.size(), CV_32FC1, cv::Scalar(0.0f));
  has = cv::Mat(grey.size(), CV_8UC1, cv::Scalar(0));
  double sum = 0.0;
  int count = 0;
  for (int r = 0; r < grey.rows; ++r) {
    for (int c = 0; c < grey.cols; ++c) {
      const int at = along_columns ? c : r, length = along_columns ? grey.cols : grey.rows;
      const int before = at - 1, after = at + 1;
      if (before < 0 || after >= length) continue;
      const int r0 = along_columns ? r : before, c0 = along_columns ? before : c;
      const int r1 = along_columns ? r : after, c1 = along_columns ? after : c;
      if (!mask.at<std::uint8_t>(r0, c0) || !mask.at<std::uint8_t>(r1, c1)) continue;
      const float g = 0.5f * std::abs(grey.at<float>(r1, c1) - grey.at<float>(r0, c0));
      gradient.at<float>(r, c) = g;
      has.at<std::uint8_t>(r, c) = 255;
      sum += g;
      ++count;
    }
  }
  if (count == 0 || !(sum > 0.0)) {
    has.setTo(cv::Scalar(0));
    return;
  }
  gradient *= static_cast<float>(count / sum);
}

// The largest normalised autocorrelation of the detrended profile at a local maximum
// between min_lag and max_lag [px], with that lag; lags the profile cannot hold three
// times are not tried.
std::pair<double, int> strongestPeriod(const Profile& p, int min_lag, int max_lag) {
  const int n = static_cast<int>(p.value.size());
  const int half = std::max(1, static_cast<int>(kTrendWindowPeriods * max_lag / 2));
  std::vector<double> detrended(p.value.size(), 0.0);
  int valid_count = 0;
  for (int i = 0; i < n; ++i) {
    if (!p.valid[static_cast<std::size_t>(i)]) continue;
    ++valid_count;
    double sum = 0.0;
    int count = 0;
    for (int k = std::max(0, i - half); k <= std::min(n - 1, i + half); ++k) {
      if (p.valid[static_cast<std::size_t>(k)]) sum += p.value[static_cast<std::size_t>(k)], ++count;
    }
    detrended[static_cast<std::size_t>(i)] = p.value[static_cast<std::size_t>(i)] - sum / count;
  }
  double variance = 0.0;
  for (int i = 0; i < n; ++i) {
    if (p.valid[static_cast<std::size_t>(i)]) variance += detrended[static_cast<std::size_t>(i)] * detrended[static_cast<std::size_t>(i)];
  }
  if (valid_count < 3 * min_lag || !(variance > 0.0)) return {0.0, 0};
  variance /= valid_count;
  const int last = std::min(max_lag, valid_count / 3);
  std::vector<double> rho(static_cast<std::size_t>(last + 2), 0.0);
  for (int lag = std::max(1, min_lag - 1); lag <= last + 1 && lag < n; ++lag) {
    double sum = 0.0;
    int count = 0;
    for (int i = 0; i + lag < n; ++i) {
      if (!p.valid[static_cast<std::size_t>(i)] || !p.valid[static_cast<std::size_t>(i + lag)]) continue;
      sum += detrended[static_cast<std::size_t>(i)] * detrended[static_cast<std::size_t>(i + lag)];
      ++count;
    }
    if (count > 0) rho[static_cast<std::size_t>(lag)] = sum / (count * variance);
  }
  const auto peak = [&](int lag) {
    const double r = rho[static_cast<std::size_t>(lag)];
    return r >= rho[static_cast<std::size_t>(lag - 1)] && r >= rho[static_cast<std::size_t>(lag + 1)];
  };
  double best = 0.0;
  for (int lag = min_lag; lag <= last; ++lag) {
    if (peak(lag)) best = std::max(best, rho[static_cast<std::size_t>(lag)]);
  }
  // A period repeats at its multiples as strongly: the shortest peak near the best is it.
  for (int lag = min_lag; lag <= last; ++lag) {
    if (peak(lag) && rho[static_cast<std::size_t>(lag)] >= kFundamentalShare * best && best > 0.0) {
      return {rho[static_cast<std::size_t>(lag)], lag};
    }
  }
  return {0.0, 0};
}

// How far a profile's joints stand out as lines: the profile folded at `lag` [px] (the
// mean of each phase over the periods), its highest phase's mean over its median phase's.
// A joint a pixel or two wide in every period makes one phase stand out; a pattern whose
// autocorrelation repeats without lines (a photograph of planks repeating along their
// length, the patches' own blur) spreads its gradient over the phases.
double lineContrast(const Profile& p, int lag) {
  if (lag <= 0) return 0.0;
  const std::size_t period = static_cast<std::size_t>(lag);
  std::vector<double> sum(period, 0.0);
  std::vector<int> count(period, 0);
  for (std::size_t i = 0; i < p.value.size(); ++i) {
    if (!p.valid[i]) continue;
    sum[i % period] += p.value[i];
    ++count[i % period];
  }
  std::vector<double> phase;
  for (std::size_t k = 0; k < period; ++k) {
    if (count[k] > 0) phase.push_back(sum[k] / count[k]);
  }
  if (phase.empty()) return 0.0;
  const double highest = *std::max_element(phase.begin(), phase.end());
  const auto middle = phase.begin() + static_cast<std::ptrdiff_t>(phase.size() / 2);
  std::nth_element(phase.begin(), middle, phase.end());
  return *middle > 0.0 ? highest / *middle : 0.0;
}

}  // namespace

JointGrid jointGridOfFace(const std::vector<const SurfacePatch*>& patches, double patch_size_m) {
  JointGrid result;
  if (patches.empty() || !(patch_size_m > 0.0)) return result;
  const int n = patches.front()->bgr.rows;
  double s_min = patches.front()->s_m, s_max = s_min, t_min = patches.front()->t_m, t_max = t_min;
  for (const SurfacePatch* patch : patches) {
    s_min = std::min(s_min, patch->s_m), s_max = std::max(s_max, patch->s_m);
    t_min = std::min(t_min, patch->t_m), t_max = std::max(t_max, patch->t_m);
  }
  // The patches tile their rectangle, one patch size apart: laid side by side they are the
  // face seen face-on (row 0 at the largest t, as in each patch).
  const int columns = static_cast<int>(std::lround((s_max - s_min) / patch_size_m)) + 1;
  const int rows = static_cast<int>(std::lround((t_max - t_min) / patch_size_m)) + 1;
  cv::Mat gradient_s(rows * n, columns * n, CV_32FC1, cv::Scalar(0.0f)), gradient_t(gradient_s.size(), CV_32FC1, cv::Scalar(0.0f));
  cv::Mat has_s(gradient_s.size(), CV_8UC1, cv::Scalar(0)), has_t(gradient_s.size(), CV_8UC1, cv::Scalar(0));
  for (const SurfacePatch* patch : patches) {
    const int i = static_cast<int>(std::lround((patch->s_m - s_min) / patch_size_m));
    const int j = static_cast<int>(std::lround((t_max - patch->t_m) / patch_size_m));
    cv::Mat g8, g;
    cv::cvtColor(patch->bgr, g8, cv::COLOR_BGR2GRAY);
    g8.convertTo(g, CV_32F);
    cv::log(g + 1.0f, g);  // a joint is a ratio of brightness, whatever the shading
    const cv::Rect at(i * n, j * n, n, n);
    cv::Mat gradient, has;
    patchGradient(g, patch->mask, true, gradient, has);
    gradient.copyTo(gradient_s(at)), has.copyTo(has_s(at));
    patchGradient(g, patch->mask, false, gradient, has);
    gradient.copyTo(gradient_t(at)), has.copyTo(has_t(at));
  }
  const double pixel_m = patch_size_m / n;
  const int min_lag = std::max(2, static_cast<int>(std::lround(kMinJointPeriodM / pixel_m)));
  const int max_lag = static_cast<int>(std::lround(kMaxJointPeriodM / pixel_m));
  const Profile profile_s = jointProfile(gradient_s, has_s, true), profile_t = jointProfile(gradient_t, has_t, false);
  const auto [strength_s, lag_s] = strongestPeriod(profile_s, min_lag, max_lag);
  const auto [strength_t, lag_t] = strongestPeriod(profile_t, min_lag, max_lag);
  result.strength_s = strength_s, result.period_s_m = lag_s * pixel_m;
  result.strength_t = strength_t, result.period_t_m = lag_t * pixel_m;
  result.line_contrast_s = lineContrast(profile_s, lag_s);
  result.line_contrast_t = lineContrast(profile_t, lag_t);
  result.grid = strength_s >= kGridStrength && strength_t >= kGridStrength && result.line_contrast_s >= kLineContrast &&
                result.line_contrast_t >= kLineContrast;
  return result;
}

}  // namespace room_reverb::core::material_detail
