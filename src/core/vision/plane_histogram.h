#pragma once
// Planes as peaks of a 1-D histogram of coordinates along a known normal direction (z for
// floor and ceiling, the two wall directions once the room's yaw is known).
#include <algorithm>
#include <cmath>
#include <vector>

namespace room_reverb::core::layout {

// How far a plane's points spread along its normal. Stereo depth noise is a fraction of
// the range, along the ray; a ray of length r meeting a plane d metres from the rig moves
// a point along the plane's normal by r * cos(incidence) = d times that fraction, so the
// spread is the same all over the plane and grows with the plane's distance.
struct PlaneSpread {
  double min_half_width_m = 0.06;  // never narrower: voxel quantisation, surface roughness
  double noise_fraction = 0.01;    // 1-sigma depth noise over range
  double sigmas = 3.0;             // half width of a plane's window, in sigmas
  double halfWidth(double distance_m) const {
    return std::max(min_half_width_m, sigmas * noise_fraction * std::abs(distance_m));
  }
};

struct PlanePeak {
  double position_m = 0.0;  // along the axis (the plane's distance from the rig, signed)
  double support = 0.0;     // points within the plane's window
  double contrast = 0.0;    // point density in the window over that in the flanks beside it
};

class PlaneHistogram {
 public:
  // `values` are coordinates along the axis; `bin_m` the histogram's resolution.
  PlaneHistogram(const std::vector<double>& values, double bin_m);

  // Local maxima of the smoothed histogram, one per window (non-maximum suppression over
  // the plane's own half width), with support >= min_support and contrast >= min_contrast,
  // sorted by position. Contrast compares the window with the two flanks of twice its
  // width beside it: a plane is a thin dense layer, a blob or a sloped surface is not.
  std::vector<PlanePeak> peaks(const PlaneSpread& spread, double min_support, double min_contrast) const;

  // Points in [from, to] (to the nearest bin edge).
  double count(double from, double to) const;

 private:
  double bin_;
  double origin_;
  std::vector<double> counts_;
  std::vector<double> prefix_;  // prefix_[i] = sum of counts_[0, i)
};

// The plane's position refined from the raw points: the weighted median of the values
// in a window centred on the current estimate, repeated until it settles. The median in a
// centred window is unbiased for a symmetric spread and ignores the occasional furniture
// face or outlier that a mean would follow. Raw points weighted by one over their voxel's
// count, not voxel centroids: where a plane lies on a voxel boundary the centroids
// gather in two layers either side of it, and the median of two layers jumps between them.
// Returns the position and sets `support` to the weight in the final window.
double refinePlanePosition(const std::vector<double>& values, const std::vector<double>& weights, double start_m,
                           double half_width_m, double* support = nullptr);

}  // namespace room_reverb::core::layout
