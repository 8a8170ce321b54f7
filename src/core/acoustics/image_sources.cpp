#include "room_reverb/acoustics/image_sources.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "room_reverb/acoustics/edge_diffraction.h"
#include "room_reverb/acoustics/room_shape.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

struct Search {
  const AcousticScene& scene;
  const Eigen::Vector3d& source;
  const Eigen::Vector3d& listener;
  const PropagationModel& model;
  const ImageSourceOptions& options;
  std::vector<SpecularPath> paths;
  // Image chain: images[k] is the source mirrored in planes[0..k].
  std::vector<Eigen::Vector3d> images;
  std::vector<std::size_t> planes;
};

Eigen::Vector3d mirror(const Eigen::Vector3d& point, const ScenePlane& plane) {
  return point - 2.0 * (plane.normal.dot(point) - plane.offset) * plane.normal;
}

double signedDistance(const Eigen::Vector3d& point, const ScenePlane& plane) {
  return plane.normal.dot(point) - plane.offset;
}

// Walks the path back from the listener to the source through the chain of planes and
// returns the hit triangles (source side first), or false if any leg is blocked or a
// reflection point misses its plane's triangles.
bool validatePath(const Search& s, std::vector<std::size_t>& triangles, Eigen::Vector3d& first_leg_direction,
                  std::vector<Eigen::Vector3d>* points = nullptr) {
  const std::size_t order = s.planes.size();
  triangles.assign(order, 0);
  if (points != nullptr) points->assign(order, Eigen::Vector3d::Zero());
  Eigen::Vector3d from = s.listener;
  for (std::size_t k = order; k-- > 0;) {
    const Eigen::Vector3d target = s.images[k];
    const Eigen::Vector3d direction = (target - from).normalized();
    const ScenePlane& plane = s.scene.planes()[s.planes[k]];
    // Distance along the ray to the plane; the first thing hit must be a triangle of it.
    const double denominator = plane.normal.dot(direction);
    if (std::abs(denominator) < 1e-12) return false;
    const double t_plane = (plane.offset - plane.normal.dot(from)) / denominator;
    if (t_plane <= 1e-6) return false;
    const RayHit hit = s.scene.geometry().intersect(from, direction, 1e-6);
    if (!hit.hit || s.scene.planeOf(hit.triangle) != s.planes[k]) return false;
    if (std::abs(hit.distance_m - t_plane) > 1e-3) return false;
    triangles[k] = hit.triangle;
    from = from + t_plane * direction;
    if (points != nullptr) (*points)[k] = from;
  }
  // Last leg: from the first reflection point (or the listener) to the source.
  if (s.scene.geometry().occluded(from, s.source, 1e-4)) return false;
  first_leg_direction = (from - s.source).normalized();
  return true;
}

// Per band, what air and the source's directivity (leaving along `leaving`) make of a path
// `distance_m` long, times the reflections' factors along `triangles`.
OctaveBandValues pathGains(const Search& s, const Eigen::Vector3d& leaving, double distance_m,
                           const std::vector<std::size_t>& triangles) {
  OctaveBandValues gains{};
  const double directivity = s.model.directivity.pressureGain(leaving);
  for (int b = 0; b < kOctaveBandCount; ++b) {
    double gain = directivity / distance_m;
    for (std::size_t triangle : triangles) {
      const AcousticMaterial& material = s.scene.material(triangle);
      gain *= std::sqrt(1.0 - material.absorption[b]);
      if (s.options.specular_share_only) gain *= std::sqrt(1.0 - material.scattering[b]);
    }
    // Air absorbs energy as exp(-m d): pressure as exp(-m d / 2).
    gain *= std::exp(-0.5 * s.model.air_attenuation_per_m[b] * distance_m);
    gains[static_cast<std::size_t>(b)] = gain;
  }
  return gains;
}

// Per band, the product over the path's reflections (at `points`, on `triangles`, source
// side first) of the specular energy share their surfaces' sizes leave (Rindel's strip
// model, diffraction_scattering.h), d1 and d2 the unfolded path lengths on either side.
OctaveBandValues diffractionShares(const Search& s, const std::vector<Eigen::Vector3d>& points,
                                   const std::vector<std::size_t>& triangles) {
  const OctaveBandValues& centres_hz = s.scene.bandCentresHz();
  std::vector<double> along(points.size() + 2, 0.0);  // unfolded distance from the source to each point
  Eigen::Vector3d previous = s.source;
  for (std::size_t k = 0; k <= points.size(); ++k) {
    const Eigen::Vector3d next = k < points.size() ? points[k] : s.listener;
    along[k + 1] = along[k] + (next - previous).norm();
    previous = next;
  }
  const double total = along[points.size() + 1];
  OctaveBandValues shares;
  shares.fill(1.0);
  Eigen::Vector3d from = s.source;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Eigen::Vector3d incident = (points[k] - from).normalized();
    const double distance = characteristicDistance(along[k + 1], total - along[k + 1]);
    for (int b = 0; b < kOctaveBandCount; ++b) {
      shares[b] *= specularShare(s.scene.surfaceExtent(triangles[k]), incident, distance,
                                 centres_hz[b], s.model.speed_of_sound_m_s);
    }
    from = points[k];
  }
  return shares;
}

// The direct sound in a scene with known objects (diffract_direct_sound), as
// directSoundPastObjects hears it. False when it is blocked and no single edge clears it.
bool addDirectSound(Search& s, bool in_view) {
  const double c = s.model.speed_of_sound_m_s;
  const std::optional<DirectSoundPast> past =
      directSoundPastObjects(s.scene.roomShape()->objects, s.source, s.listener, in_view, c, s.scene.bandCentresHz());
  if (!past) return false;
  SpecularPath path;
  path.order = 0;
  // Around the object it leaves the source towards the first edge and reaches the
  // listener from the last.
  const Eigen::Vector3d first = past->bent ? past->detour->turns.front() : s.listener;
  const Eigen::Vector3d last = past->bent ? past->detour->turns.back() : s.source;
  path.distance_m = past->bent ? past->detour->length_m : (s.source - s.listener).norm();
  path.arrival_direction = (last - s.listener).normalized();
  path.image_position = s.listener + path.distance_m * path.arrival_direction;
  path.delay_s = path.distance_m / c;
  path.pressure_gain = pathGains(s, (first - s.source).normalized(), path.distance_m, {});
  for (int b = 0; b < kOctaveBandCount; ++b) path.pressure_gain[b] *= past->gains[b];
  s.paths.push_back(std::move(path));
  return true;
}

void addPath(Search& s) {
  std::vector<std::size_t> triangles;
  Eigen::Vector3d leaving;
  std::vector<Eigen::Vector3d> points;
  const bool diffracting = s.options.diffraction_scattering && s.options.specular_share_only && !s.planes.empty();
  const bool valid = validatePath(s, triangles, leaving, diffracting ? &points : nullptr);
  if (s.planes.empty() && s.options.diffract_direct_sound && s.scene.roomShape() != nullptr &&
      !s.scene.roomShape()->objects.empty()) {
    addDirectSound(s, valid);
    return;
  }
  if (!valid) return;
  SpecularPath path;
  path.order = static_cast<int>(s.planes.size());
  path.image_position = s.planes.empty() ? s.source : s.images.back();
  const Eigen::Vector3d to_image = path.image_position - s.listener;
  path.distance_m = to_image.norm();
  path.delay_s = path.distance_m / s.model.speed_of_sound_m_s;
  path.arrival_direction = to_image / path.distance_m;
  path.triangles = triangles;
  path.pressure_gain = pathGains(s, leaving, path.distance_m, triangles);
  if (diffracting) {
    const OctaveBandValues shares = diffractionShares(s, points, triangles);
    for (int b = 0; b < kOctaveBandCount; ++b) path.pressure_gain[b] *= std::sqrt(shares[b]);
  }
  s.paths.push_back(std::move(path));
}

void expand(Search& s) {
  addPath(s);
  if (static_cast<int>(s.planes.size()) >= s.options.max_order) return;
  const Eigen::Vector3d current = s.images.empty() ? s.source : s.images.back();
  const auto& planes = s.scene.planes();
  for (std::size_t p = 0; p < planes.size(); ++p) {
    if (!s.planes.empty() && s.planes.back() == p) continue;  // mirroring twice undoes itself
    // A reflection in p needs the (image) source and the listener on the same side of it.
    const double source_side = signedDistance(current, planes[p]);
    const double listener_side = signedDistance(s.listener, planes[p]);
    if (source_side * listener_side <= 0.0) continue;
    s.images.push_back(mirror(current, planes[p]));
    s.planes.push_back(p);
    expand(s);
    s.images.pop_back();
    s.planes.pop_back();
  }
}

// Candidates per order up to `order`, as expand() visits them (no path checked).
void countCandidates(const std::vector<ScenePlane>& planes, const Eigen::Vector3d& image, const Eigen::Vector3d& listener,
                     std::size_t last_plane, int depth, int order, std::vector<double>& per_order) {
  per_order[static_cast<std::size_t>(depth)] += 1.0;
  if (depth >= order) return;
  for (std::size_t p = 0; p < planes.size(); ++p) {
    if (p == last_plane) continue;
    if (signedDistance(image, planes[p]) * signedDistance(listener, planes[p]) <= 0.0) continue;
    countCandidates(planes, mirror(image, planes[p]), listener, p, depth + 1, order, per_order);
  }
}

}  // namespace

std::optional<std::vector<Eigen::Vector3d>> specularReflectionPoints(const AcousticScene& scene,
                                                                     const Eigen::Vector3d& source,
                                                                     const Eigen::Vector3d& listener,
                                                                     const std::vector<std::size_t>& planes) {
  const PropagationModel model;
  const ImageSourceOptions options;
  Search s{scene, source, listener, model, options, {}, {}, {}};
  Eigen::Vector3d current = source;
  for (std::size_t p : planes) {
    if (p >= scene.planes().size()) return std::nullopt;
    const ScenePlane& plane = scene.planes()[p];
    if (signedDistance(current, plane) * signedDistance(listener, plane) <= 0.0) return std::nullopt;
    current = mirror(current, plane);
    s.images.push_back(current);
    s.planes.push_back(p);
  }
  std::vector<std::size_t> triangles;
  Eigen::Vector3d leaving;
  std::vector<Eigen::Vector3d> points;
  if (!validatePath(s, triangles, leaving, &points)) return std::nullopt;
  return points;
}

std::optional<std::vector<Eigen::Vector3d>> specularPathPoints(const AcousticScene& scene, const Eigen::Vector3d& source,
                                                               const Eigen::Vector3d& listener, const SpecularPath& path) {
  std::vector<std::size_t> planes;
  for (std::size_t triangle : path.triangles) {
    if (triangle >= scene.mesh().triangleCount()) return std::nullopt;
    planes.push_back(scene.planeOf(triangle));
  }
  auto points = specularReflectionPoints(scene, source, listener, planes);
  if (!points) return std::nullopt;
  points->insert(points->begin(), source);
  points->push_back(listener);
  return points;
}

bool specularPathValid(const AcousticScene& scene, const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                       const std::vector<std::size_t>& planes) {
  return specularReflectionPoints(scene, source, listener, planes).has_value();
}

double estimatedImageCandidates(const AcousticScene& scene, const Eigen::Vector3d& source,
                                const Eigen::Vector3d& listener, int order) {
  constexpr int kCounted = 3;
  const int counted = std::min(order, kCounted);
  std::vector<double> per_order(static_cast<std::size_t>(counted) + 1, 0.0);
  countCandidates(scene.planes(), source, listener, scene.planes().size(), 0, counted, per_order);
  double total = 0.0;
  for (double n : per_order) total += n;
  if (order <= counted || per_order.back() <= 0.0) return total;
  const double growth = per_order[counted] / std::max(1.0, per_order[counted - 1]);
  double level = per_order.back();
  for (int k = counted + 1; k <= order; ++k) total += (level *= growth);
  return total;
}

std::vector<SpecularPath> computeImageSources(const AcousticScene& scene, const Eigen::Vector3d& source,
                                              const Eigen::Vector3d& listener, const PropagationModel& model,
                                              const ImageSourceOptions& options) {
  if (options.max_order < 0) throw InputError("image-source order must be 0 or more");
  const double candidates = estimatedImageCandidates(scene, source, listener, options.max_order);
  if (candidates > options.max_candidates) {
    int fits = 0;
    while (fits + 1 < options.max_order && estimatedImageCandidates(scene, source, listener, fits + 1) <= options.max_candidates) ++fits;
    char count[32];
    std::snprintf(count, sizeof count, "%.1e", candidates);
    throw InputError("image-source order " + std::to_string(options.max_order) + " over the room's " +
                     std::to_string(scene.planes().size()) + " planes means about " + count +
                     " candidate paths, more than can be checked in minutes: use order " + std::to_string(fits) +
                     " or less (the rays carry the later reflections)");
  }
  Search search{scene, source, listener, model, options, {}, {}, {}};
  expand(search);
  return search.paths;
}

}  // namespace room_reverb::core
