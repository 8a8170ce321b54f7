#include "planar_disparity.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "room_reverb/common/parallel_rows.h"
#include "room_reverb/vision/equirect.h"

namespace room_reverb::core::stereo_detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kPhotometricIterations = 4;
// A step that moves the plane's disparity by less than this anywhere on the tile [px] ends
// the iterations.
constexpr double kConvergedPx = 0.005;
// A pixel is on the tile's plane while its disparity is within this of the plane's [px]:
// the matcher's pull towards whole pixels moves a disparity by up to half a pixel, and
// sensor noise adds a little.
constexpr double kOnPlanePx = 0.75;
// One plane explains the tile when this share of its ranged pixels is on it: a tile across
// an object's edge or a room's corner is left to the per-pixel step.
constexpr double kMinOnPlaneShare = 0.8;
// The photometric plane is kept where its disparity at the tile's centre is known to this
// [px, one standard deviation, from the grey residuals]: a twentieth of a pixel is 0.6 %
// of the range at 8 m. A tile with less texture keeps the matcher's disparities.
constexpr double kMaxDisparityStdPx = 0.05;
// Two tiles' planes agree at a pixel within this [px]: three times the standard deviation
// a kept plane's disparity may have at its tile's centre.
constexpr double kPlanesAgreePx = 0.15;

// A ranged pixel of the tile, with its inverse range rho and the first two derivatives
// of its disparity in rho [px m, px m^2]: a plane's disparity at the pixel is taken from
// their second-order expansion about the pixel's own rho. Within a pixel of the matcher's
// disparity the expansion's error is under 1e-4 px at 1 m, the nearest plane a tile
// usually holds, and it spares an arctangent per pixel per step.
struct Sample {
  int v, u;
  Eigen::Vector3d ray;
  double d_px;
  double rho, slope, curvature;

  // The disparity [px] of inverse range `to` along this pixel's ray, and its derivative.
  double disparityAt(double to) const {
    const double delta = to - rho;
    return d_px + delta * (slope + 0.5 * curvature * delta);
  }
  double slopeAt(double to) const { return slope + curvature * (to - rho); }
};

// Least squares of rho = m.x over the samples marked in `use`, each residual counted in
// pixels of disparity (the slope d gamma / d rho in pixels at the sample's own rho).
bool fitInverseRangePlane(const std::vector<Sample>& samples, const std::vector<char>& use, Eigen::Vector3d& m) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  int used = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!use[i]) continue;
    const Sample& s = samples[i];
    const double w = s.slope * s.slope;
    normal += w * s.ray * s.ray.transpose();
    rhs += w * s.rho * s.ray;
    ++used;
  }
  if (used < 3) return false;
  const Eigen::LDLT<Eigen::Matrix3d> solver(normal);
  if (solver.info() != Eigen::Success) return false;
  m = solver.solve(rhs);
  return m.allFinite();
}

double planeDisparityPx(const Sample& s, const Eigen::Vector3d& m) { return s.disparityAt(m.dot(s.ray)); }

// Whether plane m explains the samples: kMinOnPlaneShare of them within kOnPlanePx of it.
// `on`, when given, marks those samples.
bool explains(const std::vector<Sample>& samples, const Eigen::Vector3d& m, std::vector<char>* on = nullptr) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const bool near = std::abs(samples[i].d_px - planeDisparityPx(samples[i], m)) <= kOnPlanePx;
    if (on != nullptr) (*on)[i] = near;
    count += near;
  }
  return static_cast<double>(count) >= kMinOnPlaneShare * static_cast<double>(samples.size());
}

// The directions of the image's pixels (vision/equirect.h; a pixel's polar angle theta
// from the zenith is 90 degrees less its elevation: sin theta = cos elevation), and each
// ranged pixel's inverse range, computed once for both grids of tiles.
struct ImageGeometry {
  EquirectDirections directions;
  cv::Mat rho;  // CV_32FC1 [1/m], NaN where there is no disparity
};

ImageGeometry imageGeometry(const cv::Mat& disparity, const PlanarRefinementGrid& grid) {
  ImageGeometry g;
  const int h = disparity.rows, w = disparity.cols;
  const double pixel_rad = kPi / h;
  g.directions = equirectDirections(EquirectGeometry{w, h});
  const std::vector<double>& sin_theta = g.directions.cos_elevation;
  const std::vector<double>& cos_theta = g.directions.sin_elevation;
  g.rho = cv::Mat(disparity.size(), CV_32FC1, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  forEachRow(h, grid.threads, [&](int v) {
    const float* d = disparity.ptr<float>(v);
    float* rho = g.rho.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      if (!std::isfinite(d[u])) continue;
      // r = b sin(theta - gamma) / sin(gamma) (spherical_stereo.h), with sin(theta - gamma)
      // from the row's sine and cosine: one sine and cosine per pixel.
      const double gamma = d[u] * pixel_rad;
      const double sin_g = std::sin(gamma), cos_g = std::cos(gamma);
      const auto row = static_cast<std::size_t>(v);
      rho[u] = static_cast<float>(sin_g / (grid.baseline_m * (sin_theta[row] * cos_g - cos_theta[row] * sin_g)));
    }
  });
  return g;
}

// The sample of pixel (v, u) with disparity d_px [px] and inverse range rho.
Sample sampleOf(const ImageGeometry& g, int v, int u, double d_px, double rho, double baseline_m, double pixel_rad) {
  const double sin_t = g.directions.cos_elevation[static_cast<std::size_t>(v)];
  const double cos_t = g.directions.sin_elevation[static_cast<std::size_t>(v)];
  // gamma(rho) = theta - atan2(sin, cos + b rho): gamma' = b sin / (sin^2 + C^2) and
  // gamma'' = -2 b^2 sin C / (sin^2 + C^2)^2 with C = cos + b rho.
  const double b = baseline_m, c = cos_t + b * rho, q = sin_t * sin_t + c * c;
  return {v, u, g.directions.at(u, v), d_px, rho, b * sin_t / q / pixel_rad, -2.0 * b * b * sin_t * c / (q * q) / pixel_rad};
}

// Grey level and its derivative at fractional column x of a row; false outside the row.
bool sampleRow(const EpipolarImage& image, int row, double x, double& value, double& slope) {
  const double base = std::floor(x);
  const int k = static_cast<int>(base);
  if (k < 0 || k + 1 >= image.grey.cols) return false;
  const double a = x - base;
  const float* g = image.grey.ptr<float>(row);
  const float* gx = image.dx.ptr<float>(row);
  value = (1.0 - a) * g[k] + a * g[k + 1];
  slope = (1.0 - a) * gx[k] + a * gx[k + 1];
  return true;
}

// The photometric cost of plane m over the samples on it (the mean squared grey
// difference r = L(c) - R(c - d(m))) and its Gauss-Newton normal equations.
struct PhotometricSystem {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  double cost = 0.0;
  int used = 0;
};

bool photometricSystem(const EpipolarImage& left, const EpipolarImage& right, const std::vector<Sample>& samples,
                       const std::vector<char>& on_plane, const PlanarRefinementGrid& grid, const Eigen::Vector3d& m,
                       PhotometricSystem& system) {
  // The normal matrix's six distinct terms and the gradient, summed as scalars.
  double n00 = 0, n01 = 0, n02 = 0, n11 = 0, n12 = 0, n22 = 0, g0 = 0, g1 = 0, g2 = 0, cost = 0;
  int used = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!on_plane[i]) continue;
    const Sample& s = samples[i];
    const double rho = m.dot(s.ray);
    if (!(rho > 0.0)) return false;
    const double d = s.disparityAt(rho);
    const int row = s.u + grid.seam_padding_px, col = s.v + grid.pole_padding_px;
    double r = 0.0, r_slope = 0.0;
    if (!sampleRow(right, row, col - d, r, r_slope)) continue;
    const double residual = left.grey.ptr<float>(row)[col] - r;
    // dr/dd = R'(c - d), dd/dm = (dd/drho) x.
    const double k = r_slope * s.slopeAt(rho);
    const double j0 = k * s.ray.x(), j1 = k * s.ray.y(), j2 = k * s.ray.z();
    n00 += j0 * j0, n01 += j0 * j1, n02 += j0 * j2, n11 += j1 * j1, n12 += j1 * j2, n22 += j2 * j2;
    g0 += j0 * residual, g1 += j1 * residual, g2 += j2 * residual;
    cost += residual * residual;
    ++used;
  }
  if (used < 16) return false;
  system.normal << n00, n01, n02, n01, n11, n12, n02, n12, n22;
  system.gradient << g0, g1, g2;
  system.cost = cost / used;
  system.used = used;
  return true;
}

// The photometric step for the tile's plane; false where the tile's grey levels do not
// fix the plane's disparity at its centre to kMaxDisparityStdPx, or the plane they choose
// no longer explains the matcher's disparities.
//
// The right image is interpolated linearly and the left read at whole pixels, which pulls
// the minimum a little towards whole-pixel disparities where the texture is sharp.
// Sampling both images half a disparity apart, or cubic interpolation, were measured
// against it on the bundled scenes and the hall of test_stereo_range_accuracy: better on
// sharp glass frames 7-9 m away, worse on the plain walls the plane is for (smooth plaster
// 6 m away 0.8 and 1.3 % against 0.7 %).
bool photometricPlane(const EpipolarImage& left, const EpipolarImage& right, const std::vector<Sample>& samples,
                      const std::vector<char>& on_plane, const PlanarRefinementGrid& grid, double pixel_rad,
                      const Eigen::Vector3d& centre_ray, double centre_theta, Eigen::Vector3d& m) {
  PhotometricSystem system;
  if (!photometricSystem(left, right, samples, on_plane, grid, m, system)) return false;
  for (int iteration = 0; iteration < kPhotometricIterations; ++iteration) {
    const Eigen::LDLT<Eigen::Matrix3d> solver(system.normal);
    if (solver.info() != Eigen::Success || !(solver.rcond() > 1e-12)) return false;
    Eigen::Vector3d step = solver.solve(system.gradient);
    if (!step.allFinite()) return false;
    // The largest change the step makes to the plane's disparity over the tile (a change of
    // tilt moves the tile's edges, not its centre); a negligible one ends the iterations.
    double moved = 0.0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (on_plane[i]) moved = std::max(moved, std::abs(step.dot(samples[i].ray) * samples[i].slope));
    }
    if (moved < kConvergedPx) break;
    // A step is taken only where it lowers the cost, halved until it does: on a texture
    // sharper than a pixel the Gauss-Newton step overshoots, and taken as it comes it
    // left a brick wall's plane 0.35 px from the minimum of its cost.
    bool lowered = false;
    for (int halving = 0; halving < 4 && !lowered; ++halving) {
      PhotometricSystem trial;
      if (!photometricSystem(left, right, samples, on_plane, grid, m - step, trial)) return false;
      if (trial.cost < system.cost) {
        m -= step;
        system = trial;
        lowered = true;
      } else {
        step *= 0.5;
      }
    }
    if (!lowered) break;
  }
  // How well the grey levels fix the plane's disparity at the tile's centre.
  const double noise = system.cost * system.used / std::max(1, system.used - 3);
  const Eigen::Matrix3d covariance = noise * system.normal.ldlt().solve(Eigen::Matrix3d::Identity());
  const double centre_slope =
      disparitySlopeInInverseRange(centre_theta, m.dot(centre_ray), grid.baseline_m) / pixel_rad;
  const double centre_std = centre_slope * std::sqrt(std::max(0.0, centre_ray.dot(covariance * centre_ray)));
  if (!(centre_std <= kMaxDisparityStdPx)) return false;
  // The moved plane must still explain the tile's disparities as the matcher's plane did:
  // a step to another minimum of the grey levels leaves them.
  return explains(samples, m);
}

// The plane's disparities of one tile written into `planes` (NaN stays where the tile's
// plane is not taken); the tile's pixels are read from `disparity`.
void fitTile(const EpipolarImage& left, const EpipolarImage& right, const cv::Mat& disparity, const ImageGeometry& geometry,
             const PlanarRefinementGrid& grid, int v0, int u0, int v1, int u1, cv::Mat& planes) {
  const int h = disparity.rows, w = disparity.cols;
  const double pixel_rad = kPi / h;
  const int area = (v1 - v0) * (u1 - u0);
  std::vector<Sample> samples;
  samples.reserve(static_cast<std::size_t>(area));
  for (int v = v0; v < v1; ++v) {
    const float* row = disparity.ptr<float>(v);
    const float* rho = geometry.rho.ptr<float>(v);
    for (int u = u0; u < u1; ++u) {
      if (rho[u] > 0.0f) samples.push_back(sampleOf(geometry, v, u, row[u], rho[u], grid.baseline_m, pixel_rad));
    }
  }
  if (2 * static_cast<int>(samples.size()) < area) return;
  // A plane through the matcher's disparities, then through those near it, twice.
  std::vector<char> use(samples.size(), 1);
  Eigen::Vector3d m;
  for (const double within : {1.5, kOnPlanePx}) {
    if (!fitInverseRangePlane(samples, use, m)) return;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      use[i] = std::abs(samples[i].d_px - planeDisparityPx(samples[i], m)) <= within;
    }
  }
  if (!fitInverseRangePlane(samples, use, m)) return;
  if (!explains(samples, m, &use)) return;
  const double centre_theta = 0.5 * (v0 + v1) * pixel_rad;
  const Eigen::Vector3d centre_ray = equirectPixelDirection(EquirectGeometry{w, h}, 0.5 * (u0 + u1) - 0.5, 0.5 * (v0 + v1) - 0.5);
  // Beyond max_range_m a tile's membership tolerance is over a tenth of its range at
  // 2048 x 1024 (0.75 of 8 px at 8 m): one wrong plane there moves a whole tile's points by
  // decimetres, where the per-pixel errors scatter (measured on the courtyard's facades
  // 9-15 m away, whose tiles' planes became slabs the layout took for objects).
  if (!(m.dot(centre_ray) * grid.max_range_m >= 1.0)) return;
  if (!photometricPlane(left, right, samples, use, grid, pixel_rad, centre_ray, centre_theta, m)) return;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!use[i]) continue;
    const double d = planeDisparityPx(samples[i], m);
    if (std::abs(d - samples[i].d_px) <= kOnPlanePx) planes.at<float>(samples[i].v, samples[i].u) = static_cast<float>(d);
  }
}

// Whether any pixel of the rectangle has a plane's disparity in `planes`.
bool anyPlane(const cv::Mat& planes, int v0, int u0, int v1, int u1) {
  for (int v = v0; v < v1; ++v) {
    const float* p = planes.ptr<float>(v);
    for (int u = u0; u < u1; ++u) {
      if (std::isfinite(p[u])) return true;
    }
  }
  return false;
}

// The planes of every tile of a grid whose tiles start at (offset, offset). With `other`
// (the other grid's planes), a tile none of whose pixels has a plane there is skipped: no
// pixel of it could take the planes' disparity.
cv::Mat fitTiles(const EpipolarImage& left, const EpipolarImage& right, const cv::Mat& disparity,
                 const ImageGeometry& geometry, const PlanarRefinementGrid& grid, int offset,
                 const cv::Mat* other = nullptr) {
  cv::Mat planes(disparity.size(), CV_32FC1, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  const int tile = grid.tile_px;
  const int first = offset > 0 ? offset - tile : 0;
  const int tile_rows = (disparity.rows - first + tile - 1) / tile;
  const int tile_cols = (disparity.cols - first + tile - 1) / tile;
  // Tiles of one row band write only their own rows.
  forEachRow(tile_rows, grid.threads, [&](int tr) {
    for (int tc = 0; tc < tile_cols; ++tc) {
      const int v0 = first + tr * tile, u0 = first + tc * tile;
      const int from_v = std::max(0, v0), from_u = std::max(0, u0);
      const int to_v = std::min(disparity.rows, v0 + tile), to_u = std::min(disparity.cols, u0 + tile);
      if (other != nullptr && !anyPlane(*other, from_v, from_u, to_v, to_u)) continue;
      fitTile(left, right, disparity, geometry, grid, from_v, from_u, to_v, to_u, planes);
    }
  });
  return planes;
}

}  // namespace

double disparitySlopeInInverseRange(double theta_rad, double rho_per_m, double baseline_m) {
  const double s = std::sin(theta_rad), c = std::cos(theta_rad) + baseline_m * rho_per_m;
  return baseline_m * s / (s * s + c * c);
}

long refineDisparityByPlanes(const EpipolarImage& left, const EpipolarImage& right, cv::Mat& disparity_px,
                             const PlanarRefinementGrid& grid, cv::Mat* taken) {
  // Two grids of tiles, the second offset by half a tile along both axes: a pixel takes the
  // planes' disparity only where the tiles of both grids that hold it chose planes that
  // agree there. A tile across a crease (a wall meeting the ceiling, a room's corner) fits
  // the surface that fills most of it and takes the other's pixels near the crease with it
  // (within kOnPlanePx, a sixth of the range at 4.5 px of disparity): the tile offset
  // across the crease holds more of the other surface and disagrees. On one plane the two
  // fits agree to their own uncertainty.
  const ImageGeometry geometry = imageGeometry(disparity_px, grid);
  const cv::Mat a = fitTiles(left, right, disparity_px, geometry, grid, 0);
  const cv::Mat b = fitTiles(left, right, disparity_px, geometry, grid, grid.tile_px / 2, &a);
  long changed = 0;
  if (taken != nullptr) *taken = cv::Mat::zeros(disparity_px.size(), CV_8UC1);
  for (int v = 0; v < disparity_px.rows; ++v) {
    const float* pa = a.ptr<float>(v);
    const float* pb = b.ptr<float>(v);
    float* d = disparity_px.ptr<float>(v);
    for (int u = 0; u < disparity_px.cols; ++u) {
      if (!(std::abs(pa[u] - pb[u]) <= kPlanesAgreePx)) continue;  // false for NaN
      d[u] = 0.5f * (pa[u] + pb[u]);
      if (taken != nullptr) taken->at<std::uint8_t>(v, u) = 255;
      ++changed;
    }
  }
  return changed;
}

}  // namespace room_reverb::core::stereo_detail
