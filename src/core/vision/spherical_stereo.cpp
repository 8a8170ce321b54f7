#include "room_reverb/vision/spherical_stereo.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <limits>
#include <sstream>

#include "room_reverb/common/error.h"
#include "room_reverb/common/parallel_rows.h"
#include "photometric_match.h"
#include "planar_disparity.h"
#include "subpixel_disparity.h"
#include "texture_snr.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

void requireUsable(const cv::Mat& image, const char* which) {
  double lo = 0.0, hi = 0.0;
  cv::minMaxLoc(image.reshape(1), &lo, &hi);
  if (hi < 8.0) throw InputError(std::string("the ") + which + " image is black (its brightest pixel is " + std::to_string(int(hi)) + ")");
  if (lo > 247.0) throw InputError(std::string("the ") + which + " image is saturated (its darkest pixel is " + std::to_string(int(lo)) + ")");
}

void validate(const cv::Mat& top, const cv::Mat& bottom, double baseline_m, const SphericalStereoOptions& o) {
  if (top.empty() || bottom.empty()) throw InputError("spherical stereo: an image is empty");
  if (top.size() != bottom.size()) {
    std::ostringstream os;
    os << "spherical stereo: the images differ in size (top " << top.cols << "x" << top.rows << ", bottom "
       << bottom.cols << "x" << bottom.rows << ")";
    throw InputError(os.str());
  }
  if (top.type() != bottom.type()) throw InputError("spherical stereo: the images differ in type");
  if (top.type() != CV_8UC3 && top.type() != CV_8UC1) throw InputError("spherical stereo: images must be 8-bit BGR or grey");
  if (top.cols != 2 * top.rows) {
    std::ostringstream os;
    os << "spherical stereo: an equirectangular image is twice as wide as high; these are " << top.cols << "x" << top.rows;
    throw InputError(os.str());
  }
  if (top.rows < 32) throw InputError("spherical stereo: images smaller than 64x32 are not usable");
  if (!(baseline_m > 0.0) || !std::isfinite(baseline_m)) {
    throw InputError("spherical stereo: the baseline must be positive and finite (got " + std::to_string(baseline_m) + " m)");
  }
  if (!(o.min_range_m > baseline_m) || !(o.max_range_m > o.min_range_m) || !(o.polar_cap_deg >= 0.0 && o.polar_cap_deg < 90.0) ||
      o.seam_padding_px < 0 || o.block_size < 1 || o.block_size % 2 == 0 || o.p1_per_channel <= 0 ||
      o.p2_per_channel <= o.p1_per_channel || o.max_hole_px < 0 || o.refinement_half_window_px < 1 ||
      o.refinement_half_window_px > 16 || o.planar_tile_px < 8 || o.planar_tile_px > 256 || !(o.planar_max_range_m > 0.0) || o.threads < 0 ||
      !(o.min_texture_snr >= 0.0 && std::isfinite(o.min_texture_snr)) || o.texture_half_window_px < 1 ||
      o.texture_half_window_px > 32) {
    throw InputError("spherical stereo: options out of range (need baseline < min_range_m < max_range_m, 0 <= "
                     "polar_cap_deg < 90, odd block_size, 0 < p1 < p2, non-negative paddings, "
                     "refinement_half_window_px 1..16, planar_tile_px 8..256, planar_max_range_m > 0, threads >= 0, "
                     "min_texture_snr >= 0, texture_half_window_px 1..32)");
  }
  requireUsable(top, "top");
  requireUsable(bottom, "bottom");
}

// The transposed image (rows = azimuth columns of the original, columns = rows of the
// original from the zenith down), continued `pole_pad` columns beyond each pole along the
// same great circle and `seam_pad` rows across the seam.
cv::Mat transposedWithPadding(const cv::Mat& image, int pole_pad, int seam_pad) {
  const int w = image.cols, h = image.rows;
  cv::Mat map_x(w + 2 * seam_pad, h + 2 * pole_pad, CV_32FC1);
  cv::Mat map_y(map_x.size(), CV_32FC1);
  for (int r = 0; r < map_x.rows; ++r) {
    const int u = ((r - seam_pad) % w + w) % w;
    const int opposite = (u + w / 2) % w;
    for (int c = 0; c < map_x.cols; ++c) {
      const int v = c - pole_pad;
      int src_u = u, src_v = v;
      if (v < 0) {  // beyond the zenith: coming down the opposite azimuth
        src_u = opposite;
        src_v = -v - 1;
      } else if (v >= h) {  // beyond the nadir
        src_u = opposite;
        src_v = 2 * h - 1 - v;
      }
      map_x.at<float>(r, c) = static_cast<float>(src_u);
      map_y.at<float>(r, c) = static_cast<float>(std::clamp(src_v, 0, h - 1));
    }
  }
  cv::Mat out;
  cv::remap(image, out, map_x, map_y, cv::INTER_NEAREST);
  return out;
}

// Holes along each row (azimuth) up to max_hole_px wide. Where the two valid neighbours
// agree within hole_surface_ratio, the hole lies on one surface (a patch too plain to
// match): it is interpolated linearly between them. Where they do not, the hole is an
// occlusion next to a depth edge, which belongs to the background: it takes the farther
// neighbour, as long as its colour stays within hole_color_tolerance of that neighbour's.
void fillHoles(SphericalDepth& depth, const cv::Mat& image, const SphericalStereoOptions& o, const cv::Mat& cap_mask) {
  const int w = depth.range_m.cols;
  const int channels = image.channels();
  for (int v = 0; v < depth.range_m.rows; ++v) {
    if (cap_mask.at<std::uint8_t>(v, 0) != 0) continue;
    float* range = depth.range_m.ptr<float>(v);
    std::uint8_t* valid = depth.valid.ptr<std::uint8_t>(v);
    std::uint8_t* filled = depth.filled.ptr<std::uint8_t>(v);
    const std::uint8_t* pixels = image.ptr<std::uint8_t>(v);
    const auto color_distance = [&](int a, int b) {
      int d = 0;
      for (int ch = 0; ch < channels; ++ch) d = std::max(d, std::abs(int(pixels[a * channels + ch]) - int(pixels[b * channels + ch])));
      return d;
    };
    for (int u = 0; u < w; ++u) {
      if (valid[u] == 0 || valid[(u + 1) % w] != 0 || filled[u] != 0) continue;
      // A hole starts at u + 1: find its end (wrapping across the seam).
      int length = 0;
      while (length <= o.max_hole_px && length < w && valid[(u + 1 + length) % w] == 0) ++length;
      if (length == 0 || length > o.max_hole_px) continue;
      const int left = u, right = (u + 1 + length) % w;
      const float near = std::min(range[left], range[right]), far = std::max(range[left], range[right]);
      const bool one_surface = far <= near * static_cast<float>(1.0 + o.hole_surface_ratio);
      const int source = range[left] >= range[right] ? left : right;
      for (int k = 1; k <= length; ++k) {
        const int at = (u + k) % w;
        if (one_surface) {
          const float a = static_cast<float>(k) / static_cast<float>(length + 1);
          range[at] = (1.0f - a) * range[left] + a * range[right];
        } else {
          if (color_distance(at, source) > o.hole_color_tolerance) continue;
          range[at] = range[source];
        }
        valid[at] = 255;
        filled[at] = 255;
      }
    }
  }
}

// Semi-global matching of a pair along the image columns (the epipolar lines of a
// vertical baseline), on transposed images (rows = azimuth columns of the original,
// columns = polar angle from the zenith down) continued across the poles and the seam.
class ColumnMatcher {
 public:
  ColumnMatcher(cv::Size size, int channels, double baseline_m, const SphericalStereoOptions& o)
      : w_(size.width), h_(size.height), seam_(o.seam_padding_px) {
    const double pixel_rad = kPi / h_;
    // The largest disparity: a point at min_range broadside to the baseline.
    const double gamma_max = std::asin(std::min(1.0, baseline_m / o.min_range_m));
    search_ = std::max(16, 16 * static_cast<int>(std::ceil(gamma_max / pixel_rad / 16.0)));
    const int area = o.block_size * o.block_size;
    sgbm_ = cv::StereoSGBM::create(0, search_, o.block_size, o.p1_per_channel * channels * area,
                                   o.p2_per_channel * channels * area, o.disp12_max_diff, o.pre_filter_cap,
                                   o.uniqueness_ratio, o.speckle_window_size, o.speckle_range,
                                   o.full_dp ? cv::StereoSGBM::MODE_HH : cv::StereoSGBM::MODE_SGBM_3WAY);
    cap_mask_ = cv::Mat::zeros(h_, 1, CV_8UC1);
    const double cap_rad = o.polar_cap_deg * kPi / 180.0;
    for (int v = 0; v < h_; ++v) {
      const double theta = (v + 0.5) * pixel_rad;
      cap_mask_.at<std::uint8_t>(v, 0) = theta < cap_rad || theta > kPi - cap_rad ? 255 : 0;
    }
    while (first_row_ < h_ && cap_mask_.at<std::uint8_t>(first_row_, 0)) ++first_row_;
    end_row_ = h_;
    while (end_row_ > first_row_ && cap_mask_.at<std::uint8_t>(end_row_ - 1, 0)) --end_row_;
    // The matcher sees only the columns between the polar caps, the `search` columns
    // before them that its first disparities look back into, and kCapMargin columns of
    // each cap so that its paths and speckle regions start and end as they do over the
    // whole image (the bundled scenes' median and 90th-percentile range errors agree to
    // within 0.001 percentage points). At 2048 x 1024 that is 1158 of 1504 columns, and the
    // matcher's time falls in proportion.
    constexpr int kCapMargin = 32;
    first_col_ = std::max(0, first_row_ - kCapMargin);
    cols_ = cv::Range(first_col_, std::min(h_ + 2 * search_, end_row_ + search_ + kCapMargin));
  }

  int search() const { return search_; }
  const cv::Mat& capMask() const { return cap_mask_; }
  cv::Mat transposed(const cv::Mat& image) const { return transposedWithPadding(image, search_, seam_); }

  // The disparities [px] on the top image's grid, NaN where the matcher found none
  // (negative: no match; 0: at infinity) and in the polar caps.
  cv::Mat match(const cv::Mat& left, const cv::Mat& right) const {
    cv::Mat matched(h_, w_, CV_32FC1, cv::Scalar(kNaN));
    if (first_row_ >= end_row_) return matched;
    cv::Mat disparity16;
    sgbm_->compute(left.colRange(cols_), right.colRange(cols_), disparity16);
    for (int v = first_row_; v < end_row_; ++v) {
      float* row = matched.ptr<float>(v);
      for (int u = 0; u < w_; ++u) {
        const short d16 = disparity16.at<short>(u + seam_, v + search_ - first_col_);
        if (d16 > 0) row[u] = static_cast<float>(d16 / 16.0);
      }
    }
    return matched;
  }

 private:
  int w_, h_, seam_, search_ = 0;
  cv::Ptr<cv::StereoSGBM> sgbm_;
  cv::Mat cap_mask_;
  int first_row_ = 0, end_row_ = 0, first_col_ = 0;
  cv::Range cols_;
};

// The two cameras' exposure difference, fitted on the pixels the matcher pairs in the
// pair at half size (photometric_match.h). A gain and an offset per channel survive area
// averaging, and at half size the matcher sees a quarter of the pixels and half the
// disparities (measured: a fifth of the full match's time), so a pair exposed differently
// is matched in full once instead of twice. Pairs too small to halve are matched as they are.
PhotometricMap exposureMap(const cv::Mat& top, const cv::Mat& bottom, double baseline_m, const SphericalStereoOptions& o) {
  constexpr int kMinHalfRows = 64;
  if (top.rows / 2 < kMinHalfRows) {
    const ColumnMatcher matcher(top.size(), top.channels(), baseline_m, o);
    return photometricMapFromMatches(top, bottom, matcher.match(matcher.transposed(top), matcher.transposed(bottom)));
  }
  const cv::Size half(top.cols / 2, top.rows / 2);
  cv::Mat top_half, bottom_half;
  cv::resize(top, top_half, half, 0.0, 0.0, cv::INTER_AREA);
  cv::resize(bottom, bottom_half, half, 0.0, 0.0, cv::INTER_AREA);
  const ColumnMatcher matcher(half, top.channels(), baseline_m, o);
  const cv::Mat matched = matcher.match(matcher.transposed(top_half), matcher.transposed(bottom_half));
  // Every second pixel at half size samples the pair as every fourth does at full size.
  return photometricMapFromMatches(top_half, bottom_half, matched, 2);
}

// Disparities of pixels whose texture the noise drowns (texture_snr.h) become NaN, except
// where a tile's plane ranged them. The noise is the larger of the two images': matching
// compares both.
void dropUntextured(cv::Mat& disparity_px, const cv::Mat& planar, const stereo_detail::EpipolarImage& left,
                    const stereo_detail::EpipolarImage& right, int pole_padding, const SphericalStereoOptions& o) {
  // The images without their padding (rows: azimuth, columns: polar angle); the filters
  // below still read the padding across the seam and the poles as the matcher did.
  const cv::Rect image(pole_padding, o.seam_padding_px, disparity_px.rows, disparity_px.cols);
  const double noise =
      std::max(stereo_detail::pixelNoiseSigma(left.grey(image)), stereo_detail::pixelNoiseSigma(right.grey(image)));
  const cv::Mat snr = stereo_detail::epipolarTextureSnr({left.grey(image), left.dx(image)}, noise, o.texture_half_window_px);
  const float threshold = static_cast<float>(o.min_texture_snr);
  forEachRow(disparity_px.rows, o.threads, [&](int v) {
    float* row = disparity_px.ptr<float>(v);
    const std::uint8_t* on_plane = planar.empty() ? nullptr : planar.ptr<std::uint8_t>(v);
    for (int u = 0; u < disparity_px.cols; ++u) {
      if (!std::isfinite(row[u]) || (on_plane != nullptr && on_plane[u] != 0)) continue;
      if (snr.at<float>(u, v) < threshold) row[u] = kNaN;
    }
  });
}

}  // namespace

double rangeFromDisparity(double theta_top_rad, double gamma_rad, double baseline_m) {
  if (!(gamma_rad > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return baseline_m * std::sin(theta_top_rad - gamma_rad) / std::sin(gamma_rad);
}

SphericalDepth computeSphericalDepth(const cv::Mat& top, const cv::Mat& bottom, double baseline_m,
                                     const SphericalStereoOptions& o) {
  validate(top, bottom, baseline_m, o);
  const int w = top.cols, h = top.rows;
  const double pixel_rad = kPi / h;
  const ColumnMatcher matcher(top.size(), top.channels(), baseline_m, o);
  const int search = matcher.search();
  const cv::Mat left = matcher.transposed(top);
  cv::Mat right = matcher.transposed(bottom);

  SphericalDepth depth;
  depth.disparity_search_px = search;
  depth.range_m = cv::Mat(h, w, CV_32FC1, cv::Scalar(kNaN));
  depth.disparity_rad = cv::Mat(h, w, CV_32FC1, cv::Scalar(kNaN));
  depth.valid = cv::Mat::zeros(h, w, CV_8UC1);
  depth.filled = cv::Mat::zeros(h, w, CV_8UC1);
  const cv::Mat& cap_mask = matcher.capMask();
  if (o.match_exposure) {
    // Where the cameras are exposed differently, the bottom image is carried onto the
    // top's before the one match at full size, and the refinement compares the carried
    // grey levels.
    const PhotometricMap map = exposureMap(top, bottom, baseline_m, o);
    if (largestLevelChange(map) > kExposureDifference) right = matcher.transposed(applyPhotometricMap(bottom, map));
  }
  const cv::Mat matched = matcher.match(left, right);
  stereo_detail::EpipolarImage left_epipolar, right_epipolar;
  if (o.subpixel_refinement || o.min_texture_snr > 0.0) {
    left_epipolar = stereo_detail::epipolarImage(left);
    right_epipolar = stereo_detail::epipolarImage(right);
  }
  cv::Mat disparity_px = matched.clone();
  cv::Mat planar;  // pixels a tile's plane ranged
  if (o.subpixel_refinement) {
    forEachRow(h, o.threads, [&](int v) {
      float* row = disparity_px.ptr<float>(v);
      for (int u = 0; u < w; ++u) {
        if (!std::isfinite(row[u])) continue;
        row[u] = static_cast<float>(stereo_detail::refineDisparity(left_epipolar, right_epipolar, u + o.seam_padding_px,
                                                                   v + search, row[u], o.refinement_half_window_px,
                                                                   o.refinement_half_window_px));
      }
    });
    if (o.planar_refinement) {
      stereo_detail::PlanarRefinementGrid grid;
      grid.baseline_m = baseline_m;
      grid.seam_padding_px = o.seam_padding_px;
      grid.pole_padding_px = search;
      grid.tile_px = o.planar_tile_px;
      grid.max_range_m = o.planar_max_range_m;
      grid.threads = o.threads;
      stereo_detail::refineDisparityByPlanes(left_epipolar, right_epipolar, disparity_px, grid, &planar);
    }
  }
  if (o.min_texture_snr > 0.0) dropUntextured(disparity_px, planar, left_epipolar, right_epipolar, search, o);
  // Rows are independent: each writes only its own row of the outputs.
  forEachRow(h, o.threads, [&](int v) {
    const double theta = (v + 0.5) * pixel_rad;
    if (cap_mask.at<std::uint8_t>(v, 0)) return;
    const float* row = disparity_px.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      const double d = row[u];
      if (!std::isfinite(d)) continue;
      const double gamma = d * pixel_rad;
      const double range = rangeFromDisparity(theta, gamma, baseline_m);
      depth.disparity_rad.at<float>(v, u) = static_cast<float>(gamma);
      if (!(range >= o.min_range_m && range <= o.max_range_m)) continue;
      depth.range_m.at<float>(v, u) = static_cast<float>(range);
      depth.valid.at<std::uint8_t>(v, u) = 255;
    }
  });
  if (o.fill_holes && o.max_hole_px > 0) fillHoles(depth, top, o, cap_mask);
  return depth;
}

}  // namespace room_reverb::core
