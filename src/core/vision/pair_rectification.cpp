#include "room_reverb/vision/pair_rectification.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <random>
#include <string>
#include <vector>

#include "norm_standard_error.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/parallel_rows.h"
#include "room_reverb/vision/equirect.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
const cv::Size kTrackingWindow(15, 15);  // Lucas-Kanade's window [px]
// Normalised grey levels as 8 bits: unit contrast this many levels about kNormalisedMid.
constexpr double kNormalisedContrast = 40.0;
constexpr double kNormalisedMid = 128.0;
const cv::TermCriteria kTrackingStop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);

struct Match {
  Eigen::Vector3d top, bottom;  // unit bearings, each camera's frame
};

// The turn as an angle-axis vector: turns of a few degrees are all two cameras on a bar
// have, and the vector's components are the small angles about the three axes.
struct Pose {
  Eigen::Vector3d turn = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation() const {
    const double angle = turn.norm();
    return angle > 0.0 ? Eigen::AngleAxisd(angle, turn / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
  }
};

// The angle between the two rays' views along the baseline: positive where the top
// camera, the higher one, sees the point further from the pole than the bottom one does.
double parallax(const Match& m, const Eigen::Matrix3d& R) {
  return std::acos(std::clamp(m.top.z(), -1.0, 1.0)) - std::acos(std::clamp((R * m.bottom).z(), -1.0, 1.0));
}

double residualOf(const Match& m, const Eigen::Matrix3d& R) {
  return epipolarResidual(m.top, m.bottom, R, Eigen::Vector3d::UnitZ());
}

// Gauss-Newton on the matches `use` (weights by Huber at `huber_rad`, 0: plain least
// squares). Returns false where the normal equations are singular.
bool gaussNewton(const std::vector<Match>& matches, const std::vector<std::size_t>& use, double huber_rad,
                 int iterations, Pose& pose, Eigen::Matrix3d* normal = nullptr) {
  constexpr double kStep = 1e-7;
  Eigen::Matrix3d JtJ;
  for (int iteration = 0; iteration < iterations; ++iteration) {
    JtJ.setZero();
    Eigen::Vector3d Jtr = Eigen::Vector3d::Zero();
    const Eigen::Matrix3d R = pose.rotation();
    std::array<Eigen::Matrix3d, 3> stepped;
    for (int k = 0; k < 3; ++k) {
      Pose step = pose;
      step.turn[k] += kStep;
      stepped[static_cast<std::size_t>(k)] = step.rotation();
    }
    for (std::size_t i : use) {
      const double r = residualOf(matches[i], R);
      Eigen::Vector3d J;
      for (int k = 0; k < 3; ++k) J[k] = (residualOf(matches[i], stepped[static_cast<std::size_t>(k)]) - r) / kStep;
      const double w = huber_rad > 0.0 && std::abs(r) > huber_rad ? huber_rad / std::abs(r) : 1.0;
      JtJ += w * J * J.transpose();
      Jtr += w * J * r;
    }
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(JtJ);
    if (lu.rank() < 3) return false;
    const Eigen::Vector3d delta = lu.solve(-Jtr);
    pose.turn += delta;
    if (delta.norm() < 1e-9) break;
  }
  if (normal != nullptr) *normal = JtJ;
  return true;
}

std::vector<std::size_t> inliersOf(const std::vector<Match>& matches, const Pose& pose, double tolerance_rad) {
  std::vector<std::size_t> inliers;
  const Eigen::Matrix3d R = pose.rotation();
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (std::abs(residualOf(matches[i], R)) < tolerance_rad && parallax(matches[i], R) > -tolerance_rad) {
      inliers.push_back(i);
    }
  }
  return inliers;
}

double medianAbsoluteResidual(const std::vector<Match>& matches, const std::vector<std::size_t>& use, const Pose& p) {
  std::vector<double> r;
  r.reserve(use.size());
  const Eigen::Matrix3d R = p.rotation();
  for (std::size_t i : use) r.push_back(std::abs(residualOf(matches[i], R)));
  if (r.empty()) return 0.0;
  std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2), r.end());
  return r[r.size() / 2];
}

void checkImages(const cv::Mat& top, const cv::Mat& bottom, const PairRectificationOptions& o) {
  const std::string who = "pair rectification: ";
  if (top.empty() || bottom.empty()) throw InputError(who + "an image is empty");
  if (top.size() != bottom.size() || top.type() != bottom.type()) {
    throw InputError(who + "the top and bottom images differ in size or type");
  }
  if (top.cols != 2 * top.rows) throw InputError(who + "the images must be equirectangular (twice as wide as high)");
  if (top.depth() != CV_8U || (top.channels() != 1 && top.channels() != 3)) {
    throw InputError(who + "the images must be 8-bit grey or colour");
  }
  if (o.feature_width < 0 || (o.feature_width > 0 && o.feature_width < 64) || o.max_features < 10 ||
      !(o.max_elevation_rad > 0.0 && o.max_elevation_rad < kPi / 2) || !(o.ratio > 0.0 && o.ratio <= 1.0) ||
      !(o.max_parallax_rad > 0.0 && o.max_parallax_rad < 1.0) || !(o.max_turn_rad > 0.0 && o.max_turn_rad < 0.5) ||
      !(o.inlier_tolerance_px > 0.0) || o.ransac_iterations < 1 || o.min_inliers < 5 || !(o.min_angle_rad >= 0.0) ||
      !(o.min_significance >= 0.0)) {
    throw InputError(who + "options out of range");
  }
}

cv::Mat featureImage(const cv::Mat& image, int width) {
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else {
    grey = image;
  }
  if (width > 0 && grey.cols > width) {
    cv::Mat small;
    cv::resize(grey, small, cv::Size(width, width / 2), 0, 0, cv::INTER_AREA);
    return small;
  }
  return grey;
}

// The image with its local mean taken out and its local contrast brought to one (a
// Gaussian window of about 4 px), as 8 bits about 128: two cameras on their own exposure
// and white balance, and the light their lenses lose towards the rim, differ by a gain
// and an offset that vary slowly across the image, and Lucas-Kanade, which compares grey
// levels, would move each match along their slope.
cv::Mat contrastNormalised(const cv::Mat& grey) {
  cv::Mat f, mean, square, variance;
  grey.convertTo(f, CV_32F);
  cv::GaussianBlur(f, mean, cv::Size(0, 0), 4.0);
  cv::GaussianBlur(f.mul(f), square, cv::Size(0, 0), 4.0);
  variance = square - mean.mul(mean);
  cv::Mat deviation;
  cv::sqrt(cv::max(variance, 1.0), deviation);
  cv::Mat normalised = (f - mean) / deviation;
  cv::Mat out;
  normalised.convertTo(out, CV_8U, kNormalisedContrast, kNormalisedMid);
  return out;
}

// Each match followed by Lucas-Kanade from `bottom_at` (its guess in the bottom image) to
// a fraction of a pixel of these images; `keep[i]` cleared for one that does not converge
// within `reach_px` of its guess.
void followMatches(const cv::Mat& top, const cv::Mat& bottom, const std::vector<cv::Point2f>& top_at,
                   std::vector<cv::Point2f>& bottom_at, std::vector<bool>& keep, double reach_px) {
  std::vector<cv::Point2f> refined = bottom_at;
  std::vector<unsigned char> status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(contrastNormalised(top), contrastNormalised(bottom), top_at, refined, status, error,
                           kTrackingWindow, 1, kTrackingStop, cv::OPTFLOW_USE_INITIAL_FLOW);
  for (std::size_t i = 0; i < top_at.size(); ++i) {
    if (!status[i] || std::hypot(refined[i].x - bottom_at[i].x, refined[i].y - bottom_at[i].y) > reach_px) keep[i] = false;
  }
  bottom_at = std::move(refined);
}

// A patch with its mean taken out and its contrast brought to one, as 8 bits about 128:
// over a patch of a few tens of pixels the two cameras' gain and offset are constant.
cv::Mat patchNormalised(const cv::Mat& patch) {
  cv::Scalar mean, deviation;
  cv::meanStdDev(patch, mean, deviation);
  cv::Mat out;
  const double gain = kNormalisedContrast / std::max(deviation[0], 1.0);
  patch.convertTo(out, CV_8U, gain, kNormalisedMid - gain * mean[0]);
  return out;
}

// The same on the images at full size, one small patch pair per match, on both cores:
// normalising the whole full-size pair would cost three times the tracking. A match too
// near the image's edge for its patch keeps its position from the feature images.
void followMatchesOnPatches(const cv::Mat& top, const cv::Mat& bottom, const std::vector<cv::Point2f>& top_at,
                            std::vector<cv::Point2f>& bottom_at, std::vector<bool>& keep, double reach_px) {
  // The tracking window's half width and the farthest a match may move.
  const int half = kTrackingWindow.width / 2 + static_cast<int>(std::ceil(reach_px)) + 1;
  const cv::Rect image(0, 0, top.cols, top.rows);
  const auto patchAt = [&](const cv::Point2f& p) {
    return cv::Rect(static_cast<int>(std::lround(p.x)) - half, static_cast<int>(std::lround(p.y)) - half,
                    2 * half + 1, 2 * half + 1);
  };
  std::vector<std::uint8_t> lost(top_at.size(), 0);
  forEachRow(static_cast<int>(top_at.size()), 0, [&](int row) {
    const auto i = static_cast<std::size_t>(row);
    if (!keep[i]) return;
    const cv::Rect top_patch = patchAt(top_at[i]), bottom_patch = patchAt(bottom_at[i]);
    if ((top_patch & image) != top_patch || (bottom_patch & image) != bottom_patch) return;
    const cv::Point2f top_origin(static_cast<float>(top_patch.x), static_cast<float>(top_patch.y));
    const cv::Point2f bottom_origin(static_cast<float>(bottom_patch.x), static_cast<float>(bottom_patch.y));
    const std::vector<cv::Point2f> from{top_at[i] - top_origin};
    std::vector<cv::Point2f> to{bottom_at[i] - bottom_origin};
    std::vector<unsigned char> status;
    std::vector<float> error;
    cv::calcOpticalFlowPyrLK(patchNormalised(top(top_patch)), patchNormalised(bottom(bottom_patch)), from, to, status,
                             error, kTrackingWindow, 0, kTrackingStop, cv::OPTFLOW_USE_INITIAL_FLOW);
    const cv::Point2f refined = to[0] + bottom_origin;
    if (!status[0] || std::hypot(refined.x - bottom_at[i].x, refined.y - bottom_at[i].y) > reach_px) {
      lost[i] = 1;
    } else {
      bottom_at[i] = refined;
    }
  });
  for (std::size_t i = 0; i < lost.size(); ++i) keep[i] = keep[i] && !lost[i];
}

// `top` and `bottom` are the feature images; `top_full` and `bottom_full` the images at
// their own size, grey.
std::vector<Match> matchFeatures(const cv::Mat& top, const cv::Mat& bottom, const cv::Mat& top_full,
                                 const cv::Mat& bottom_full, const PairRectificationOptions& o) {
  const EquirectGeometry g{top.cols, top.rows};
  // Rows within max_elevation_rad of the horizon.
  cv::Mat mask = cv::Mat::zeros(top.size(), CV_8U);
  const int margin = static_cast<int>(std::ceil((kPi / 2 - o.max_elevation_rad) / kPi * top.rows));
  mask.rowRange(margin, top.rows - margin).setTo(255);
  const cv::Ptr<cv::ORB> orb = cv::ORB::create(o.max_features);
  std::vector<cv::KeyPoint> top_points, bottom_points;
  cv::Mat top_descriptors, bottom_descriptors;
  orb->detectAndCompute(top, mask, top_points, top_descriptors);
  orb->detectAndCompute(bottom, mask, bottom_points, bottom_descriptors);
  std::vector<Match> matches;
  if (top_points.size() < 2 || bottom_points.size() < 2) return matches;
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(top_descriptors, bottom_descriptors, knn, 2);
  const double max_angle = o.max_parallax_rad + o.max_turn_rad;
  std::vector<cv::Point2f> top_at, bottom_at;
  for (const std::vector<cv::DMatch>& pair : knn) {
    if (pair.size() < 2 || pair[0].distance >= o.ratio * pair[1].distance) continue;
    const cv::Point2f a = top_points[static_cast<std::size_t>(pair[0].queryIdx)].pt;
    const cv::Point2f b = bottom_points[static_cast<std::size_t>(pair[0].trainIdx)].pt;
    if (std::acos(std::clamp(equirectPixelDirection(g, a.x, a.y).dot(equirectPixelDirection(g, b.x, b.y)), -1.0, 1.0)) >
        max_angle) {
      continue;
    }
    top_at.push_back(a);
    bottom_at.push_back(b);
  }
  if (top_at.empty()) return matches;
  // ORB places its keypoints on its pyramid's pixel grid: a match is known to half a
  // pixel of the level it was found on, 3 mrad and more at 1024 px, where the turn is
  // wanted to a few tenths. Each top keypoint is followed into the bottom image from its
  // match by Lucas-Kanade to a fraction of a pixel; one that does not converge within a
  // pixel of its match is dropped. Where the features were found on shrunk images, each
  // match is followed again on the images at their own size: a fraction of a pixel there
  // is that fraction of a smaller angle. On the six bundled scenes at 2048 px, turned
  // 0.75 degrees, the turn comes within 0.25-0.45 mrad instead of 0.18-1.18 mrad
  // (bench_visual_route, BM_PairRectification) for 2 ms, where finding the features at
  // full size doubles the rectification's time.
  std::vector<bool> keep(top_at.size(), true);
  followMatches(top, bottom, top_at, bottom_at, keep, 1.5);
  const double scale = static_cast<double>(top_full.cols) / top.cols;
  if (scale > 1.0) {
    for (auto* points : {&top_at, &bottom_at}) {
      for (cv::Point2f& p : *points) p = cv::Point2f(static_cast<float>((p.x + 0.5) * scale - 0.5),
                                                     static_cast<float>((p.y + 0.5) * scale - 0.5));
    }
    followMatchesOnPatches(top_full, bottom_full, top_at, bottom_at, keep, 1.5);
  }
  const EquirectGeometry full{top_full.cols, top_full.rows};
  for (std::size_t i = 0; i < top_at.size(); ++i) {
    if (!keep[i]) continue;
    matches.push_back({equirectPixelDirection(full, top_at[i].x, top_at[i].y),
                       equirectPixelDirection(full, bottom_at[i].x, bottom_at[i].y)});
  }
  return matches;
}

}  // namespace

double epipolarResidual(const Eigen::Vector3d& b_top, const Eigen::Vector3d& b_bottom, const Eigen::Matrix3d& R,
                        const Eigen::Vector3d& t) {
  const Eigen::Vector3d normal = t.cross(R * b_bottom);
  const double n = normal.norm();
  if (!(n > 0.0)) return 0.0;
  return std::asin(std::clamp(b_top.normalized().dot(normal / n), -1.0, 1.0));
}

PairRectification estimatePairRectification(const cv::Mat& top, const cv::Mat& bottom,
                                             const PairRectificationOptions& options) {
  checkImages(top, bottom, options);
  PairRectification out;
  if (!options.enabled) return out;
  const cv::Mat top_full = featureImage(top, 0), bottom_full = featureImage(bottom, 0);
  const cv::Mat top_grey = featureImage(top_full, options.feature_width);
  const cv::Mat bottom_grey = featureImage(bottom_full, options.feature_width);
  const std::vector<Match> matches = matchFeatures(top_grey, bottom_grey, top_full, bottom_full, options);
  out.matches = static_cast<int>(matches.size());
  if (out.matches < options.min_inliers) return out;
  const double tolerance = options.inlier_tolerance_px * 2.0 * kPi / top_grey.cols;

  // RANSAC: three matches fix the turn.
  std::mt19937_64 random(options.seed);
  std::uniform_int_distribution<std::size_t> pick(0, matches.size() - 1);
  std::vector<std::size_t> best;
  for (int iteration = 0; iteration < options.ransac_iterations; ++iteration) {
    const std::vector<std::size_t> sample{pick(random), pick(random), pick(random)};
    if (sample[0] == sample[1] || sample[1] == sample[2] || sample[0] == sample[2]) continue;
    Pose pose;
    if (!gaussNewton(matches, sample, 0.0, 4, pose) || pose.turn.norm() > options.max_turn_rad) continue;
    std::vector<std::size_t> inliers = inliersOf(matches, pose, tolerance);
    if (inliers.size() > best.size()) best = std::move(inliers);
  }
  if (static_cast<int>(best.size()) < options.min_inliers) return out;

  // The turn on every inlier, the inliers counted again with it. The baseline stays on
  // the top camera's pole: its lean shows only in the parallax of near points, a tenth
  // of the turn's signal, and on the rendered rooms a fit of it picked up 1-18 mrad of
  // lean from the matches' own errors where the bar stood true.
  Pose pose;
  std::vector<std::size_t> inliers = best;
  Eigen::Matrix3d normal;
  for (int round = 0; round < 3; ++round) {
    if (!gaussNewton(matches, inliers, 0.5 * tolerance, 8, pose, &normal)) return out;
    inliers = inliersOf(matches, pose, tolerance);
    if (static_cast<int>(inliers.size()) < options.min_inliers) return out;
  }
  out.estimated = true;
  out.residual_rad = medianAbsoluteResidual(matches, inliers, pose);
  const double sigma = 1.4826 * out.residual_rad;
  const Eigen::Matrix3d covariance = sigma * sigma * normal.inverse();
  out.bottom_to_top = pose.rotation();
  out.turn_rad = pose.turn.norm();
  out.turn_standard_error_rad = vision_detail::normStandardError<3>(pose.turn, covariance);
  out.inliers = static_cast<int>(inliers.size());
  out.applied =
      out.turn_rad >= options.min_angle_rad && out.turn_rad >= options.min_significance * out.turn_standard_error_rad;
  if (out.applied) out.bottom_rotation = out.bottom_to_top;
  return out;
}

}  // namespace room_reverb::core
