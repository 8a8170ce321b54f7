#pragma once
// The stereo's range bias, found from the room's own flat floor and ceiling. Spherical
// stereo on a vertical baseline ranges a point from the angle between the two cameras'
// views of it (its disparity). An offset in that angle bends the room: the range error
// grows with the square of the distance, so a floor seen from 1.5 m up rises towards the
// rig beyond a few metres, a ceiling sinks towards it and the far walls come in (a tenth
// of a degree at a 0.2 m baseline brings a wall 6 m away 5 % nearer). Two kinds:
//
// - the same for every pixel: a matcher's sub-pixel bias, a camera whose projection
//   places every elevation a little off;
// - one that goes with the azimuth as a cos(az) + b sin(az): the bottom camera tilted
//   against the top one (a tilt moves each point's elevation by the tilt times the sine
//   of its azimuth from the tilt's axis, whatever its elevation), as the pair's
//   rectification leaves it within a fraction of a mrad (vision/pair_rectification.h).
//
// Flat planes do not bend, so the offset is the one that puts the points of the floor and
// of the ceiling back on a plane each, found as a disparity: each point's measured
// disparity less the disparity its ray has where it meets its plane is the offset plus
// the matcher's noise. The planes' common tilt against `level` (the levelling's own
// error) is fitted alongside: it lifts the floor and the ceiling alike where an offset
// with the azimuth lifts one and lowers the other. On the route's own stereo, which has
// no offset, the estimate scatters within about 1 mrad (docs/visual-route.md), so only a
// larger offset, on which the floor and the ceiling agree, is corrected.
#include <Eigen/Core>

#include "room_reverb/vision/point_cloud.h"

namespace room_reverb::core {

struct DisparityOffsetOptions {
  bool enabled = true;
  // The offset is sought within this of zero [rad]: 10 mrad is 3.3 px at 2048 x 1024,
  // a tenth of the disparity of a point 2 m away at a 0.2 m baseline.
  double max_offset_rad = 0.01;
  // Applied only where it is at least min_offset_rad and min_significance standard errors
  // of its own fit. On rendered rooms with no offset, the constant part reaches 0.8 mrad
  // where the planes agree through the generator's ideal camera, and 1.0-1.5 mrad through
  // its consumer camera (lenses, JPEG, exposure), whose floors and ceilings then read it
  // together while the walls stand where they are; corrected, that puts the box 2.6-4.6 %
  // long. The part with the azimuth reads at most 0.12 mrad there.
  double min_offset_rad = 2e-3;
  double min_azimuth_offset_rad = 1e-3;  // of the amplitude of the part with the azimuth
  double min_significance = 4.0;
  // And only where the floor alone and the ceiling alone ask for offsets within the larger
  // of these of each other (a room without a ceiling has its floor only).
  double max_disagreement_rad = 7.5e-4;
  double max_disagreement_share = 0.4;
  double voxel_size_m = 0.05;  // one point per voxel, so area counts, not point density
  double bin_m = 0.01;         // height histogram resolution of the planes' first heights
  // The residuals' first scale [rad] (about 0.3 px at 2048 px), then their own; a point
  // counts fully within huber_scales of it and not at all beyond max_residual_scales.
  double disparity_noise_rad = 0.001;
  double huber_scales = 1.5;
  double max_residual_scales = 6.0;
  // The floor is sought below this distance under the rig's centre, the ceiling above it.
  double clear_m = 0.3;
  // The planes' first heights from the points within near_m of the rig in plan; the fit
  // then grows outwards by grow_m every other iteration.
  double near_m = 2.0;
  double grow_m = 1.0;
  // Only points on horizontal surfaces count: the normal of their neighbours within
  // neighbourhood_m within max_normal_tilt_rad of up.
  double neighbourhood_m = 0.15;
  double max_normal_tilt_rad = 0.35;
  // Points nearer than this to the poles of the baseline are left out: stereo on a
  // vertical baseline has no disparity along it.
  double min_polar_rad = 0.35;
};

// measured disparity = true disparity + offset_rad + cos_rad cos(az) + sin_rad sin(az),
// az the azimuth of the point's ray in the rig frame.
struct DisparityOffset {
  double offset_rad = 0.0;          // the same for every pixel
  double standard_error_rad = 0.0;  // of offset_rad, from the fit's scatter
  double floor_offset_rad = 0.0;    // the floor alone's, and the ceiling alone's
  double ceiling_offset_rad = 0.0;
  bool floor_fitted = false;        // whether each plane had points enough to fit alone
  bool ceiling_fitted = false;
  bool planes_agree = true;         // within max_disagreement of each other
  bool applied = false;             // large and clear enough to correct the cloud for
  // The part that goes with the azimuth: fitted only where the room shows both its floor
  // and its ceiling (with one plane it cannot be told from the plane's tilt).
  double cos_rad = 0.0, sin_rad = 0.0;
  double azimuth_standard_error_rad = 0.0;  // of its amplitude hypot(cos_rad, sin_rad)
  Eigen::Vector2d floor_azimuth = Eigen::Vector2d::Zero();  // (cos, sin) of the floor alone, and of the ceiling
  Eigen::Vector2d ceiling_azimuth = Eigen::Vector2d::Zero();
  bool azimuth_planes_agree = true;
  bool azimuth_applied = false;     // large, clear and agreed on: the cloud is corrected for it
  double plane_tilt_rad = 0.0;      // the planes' tilt against `level`, fitted alongside
  // The offset the cloud is corrected for along azimuth `az` [rad]: the parts applied.
  double correctionAt(double azimuth_rad) const;
};

// The range from the top camera a point would have if its disparity, measured with
// `offset_rad` added, had none. `range_m` from the top camera, `polar_rad` the angle of
// its direction from the rig's up axis (the baseline's direction, top camera above).
// Returns NaN where the corrected disparity is zero or less (the point is at infinity).
double rangeWithoutDisparityOffset(double range_m, double polar_rad, double baseline_m, double offset_rad);

// The offset the cloud's floor and ceiling say the stereo had. `cloud` in the rig frame
// with the top camera at (0, 0, baseline/2) (as depthToPointCloud makes it); `level`
// turns the rig frame to level (p_level = level * p_rig). InputError for a cloud of fewer
// than 1000 points or non-finite points, a baseline that is not positive, and options out
// of range.
DisparityOffset estimateDisparityOffset(const PointCloud& cloud, double baseline_m, const Eigen::Matrix3d& level,
                                        const DisparityOffsetOptions& options = {});

// The cloud with every point moved along its ray from the top camera to the range
// rangeWithoutDisparityOffset gives; points whose corrected disparity vanishes, or that lie
// within min_polar_rad of the poles, keep their place.
PointCloud removeDisparityOffset(const PointCloud& cloud, double baseline_m, double offset_rad,
                                 double min_polar_rad = DisparityOffsetOptions{}.min_polar_rad);
// The same for the parts of `offset` that are applied (DisparityOffset::correctionAt).
PointCloud removeDisparityOffset(const PointCloud& cloud, double baseline_m, const DisparityOffset& offset,
                                 double min_polar_rad = DisparityOffsetOptions{}.min_polar_rad);

}  // namespace room_reverb::core
