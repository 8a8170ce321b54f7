#include "room_reverb/acoustics/acoustic_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include "room_reverb/acoustics/relief_scattering.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPlaneNormalTolerance = 1e-4;
constexpr double kPlaneOffsetTolerance_m = 1e-3;

void checkCoefficients(const OctaveBandValues& values, const std::string& what) {
  for (double v : values) {
    if (!std::isfinite(v) || v < 0.0 || v > 1.0) {
      std::ostringstream os;
      os << what << ": coefficient " << v << " is outside [0, 1]";
      throw InputError(os.str());
    }
  }
}

// Each relief's triangles get a material of their own: their material (as resolved, with
// the overrides) with the relief's scattering combined, octave and third-octave values
// alike (the relief's octave value stands for its thirds).
void applyReliefs(TriangleMesh& mesh, std::vector<AcousticMaterial>& materials, const std::vector<SurfaceRelief>& reliefs) {
  for (const SurfaceRelief& relief : reliefs) {
    checkCoefficients(relief.scattering, "relief scattering of " + relief.surface);
    if (!hasRelief(relief.scattering)) continue;
    std::map<int, int> derived;  // base material index -> the relief's material index
    for (std::size_t t : relief.triangles) {
      if (t >= mesh.triangleCount()) throw InputError("relief of " + relief.surface + ": triangle index out of range");
      int& base = mesh.triangle_material[t];
      auto [it, added] = derived.emplace(base, static_cast<int>(materials.size()));
      if (added) {
        AcousticMaterial material = materials[static_cast<std::size_t>(base)];
        material.name += ", " + relief.surface + "'s relief";
        material.scattering = combinedScattering(material.scattering, relief.scattering);
        if (material.scattering_thirds) {
          for (OctaveBandValues& third : *material.scattering_thirds) third = combinedScattering(third, relief.scattering);
        }
        mesh.material_names.push_back(material.name);
        materials.push_back(std::move(material));
      }
      base = it->second;
    }
  }
}

}  // namespace

AcousticScene::AcousticScene(TriangleMesh mesh, const MaterialLibrary& library,
                             const MaterialOverrides& overrides, bool closed, const std::vector<SurfaceRelief>& reliefs)
    : closed_(closed) {
  validateMesh(mesh, "room mesh");
  for (const auto& name : mesh.material_names) {
    AcousticMaterial material = library.get(name);
    material.name = name;
    if (auto it = overrides.absorption.find(name); it != overrides.absorption.end()) {
      checkCoefficients(it->second, "absorption override of '" + name + "'");
      material.absorption = it->second;
      material.absorption_thirds.reset();
    }
    if (auto it = overrides.scattering.find(name); it != overrides.scattering.end()) {
      checkCoefficients(it->second, "scattering override of '" + name + "'");
      material.scattering = it->second;
      material.scattering_thirds.reset();
    }
    if (overrides.global_scattering) {
      const double s = *overrides.global_scattering;
      if (!std::isfinite(s) || s < 0.0 || s > 1.0) throw InputError("global scattering must be in [0, 1] (got " + std::to_string(s) + ")");
      material.scattering.fill(s);
      material.scattering_thirds.reset();
    }
    materials_.push_back(material);
  }
  // An override for a material no surface uses is a typo, not a no-op.
  auto requireUsed = [&](const std::map<std::string, OctaveBandValues>& map, const char* kind) {
    for (const auto& entry : map) {
      if (std::find(mesh.material_names.begin(), mesh.material_names.end(), entry.first) == mesh.material_names.end()) {
        throw InputError(std::string(kind) + " override names '" + entry.first + "', which no surface uses");
      }
    }
  };
  requireUsed(overrides.absorption, "absorption");
  requireUsed(overrides.scattering, "scattering");
  if (!overrides.global_scattering) applyReliefs(mesh, materials_, reliefs);

  // Volume (divergence theorem) and area.
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3d& a = mesh.vertices[tri[0]];
    const Eigen::Vector3d& b = mesh.vertices[tri[1]];
    const Eigen::Vector3d& c = mesh.vertices[tri[2]];
    volume_m3_ += a.dot(b.cross(c)) / 6.0;
    surface_m2_ += mesh.area(t);
  }
  volume_m3_ = std::abs(volume_m3_);

  // Group coplanar triangles: image sources reflect in planes, not in triangles.
  triangle_plane_.resize(mesh.triangleCount());
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Eigen::Vector3d n = mesh.normal(t);
    const double d = n.dot(mesh.vertices[mesh.triangles[t][0]]);
    std::size_t found = planes_.size();
    for (std::size_t p = 0; p < planes_.size(); ++p) {
      if ((planes_[p].normal - n).norm() < kPlaneNormalTolerance && std::abs(planes_[p].offset - d) < kPlaneOffsetTolerance_m) {
        found = p;
        break;
      }
    }
    if (found == planes_.size()) planes_.push_back({n, d, {}});
    planes_[found].triangles.push_back(t);
    triangle_plane_[t] = found;
  }
  patches_ = surfaceExtents(mesh, triangle_plane_, triangle_patch_);
  geometry_ = std::make_shared<const EmbreeScene>(std::move(mesh));
  band_centres_hz_ = octaveCentresHz();
}

AcousticScene AcousticScene::thirdOctaveBands(int third) const {
  if (third_ >= 0) throw InputError("the scene's bands are third octaves already");
  if (third < 0 || third > 2) throw InputError("a third of an octave is 0, 1 or 2 (got " + std::to_string(third) + ")");
  AcousticScene out = *this;
  out.third_ = third;
  for (AcousticMaterial& material : out.materials_) material = thirdOctaveMaterial(material, third);
  const std::vector<FrequencyBand> thirds = thirdsOfTheOctaves();
  for (int b = 0; b < kOctaveBandCount; ++b) out.band_centres_hz_[b] = thirds[static_cast<std::size_t>(3 * b + third)].center_hz;
  return out;
}

bool AcousticScene::hasThirdOctaveMaterials() const {
  return std::any_of(materials_.begin(), materials_.end(),
                     [](const AcousticMaterial& m) { return m.absorption_thirds || m.scattering_thirds; });
}

AcousticScene::AcousticScene(TriangleMesh mesh, const MaterialLibrary& library, const MaterialOverrides& overrides,
                             RoomShape shape, const std::vector<SurfaceRelief>& reliefs)
    : AcousticScene(std::move(mesh), library, overrides, shape.has_ceiling, reliefs) {
  // Faces of objects that overlap, stick out or lie against a wall make the divergence sum
  // count some volume twice or outside the room; the solids do not.
  if (closed_) volume_m3_ = shape.freeVolumeM3();
  shape_ = std::move(shape);
}

OctaveBandValues AcousticScene::meanAbsorption() const {
  OctaveBandValues mean{};
  for (std::size_t t = 0; t < mesh().triangleCount(); ++t) {
    const double area = mesh().area(t);
    for (int b = 0; b < kOctaveBandCount; ++b) mean[b] += area * material(t).absorption[b];
  }
  for (double& v : mean) v /= surface_m2_;
  return mean;
}

namespace {

// Closest point of triangle (a, b, c) to p, by the Voronoi regions of its vertices, edges
// and face (Ericson, Real-Time Collision Detection, 2005, sec. 5.1.5).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

}  // namespace

double AcousticScene::distanceToNearestSurface(const Eigen::Vector3d& point) const {
  const TriangleMesh& m = mesh();
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d q = closestPointOnTriangle(point, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
    nearest = std::min(nearest, (q - point).norm());
  }
  return nearest;
}

bool AcousticScene::isInside(const Eigen::Vector3d& point) const {
  if (shape_) return shape_->inBox(point) && !shape_->objectContaining(point);
  // Crossing parity along directions that avoid the axes (and so the room's edges): odd
  // means inside the room and outside every closed object. Horizontal rays only in a room
  // without a ceiling.
  const Eigen::Vector3d directions[] = {Eigen::Vector3d(0.8017, 0.5345, 0.2673).normalized(),
                                        Eigen::Vector3d(-0.6139, 0.7675, -0.1842).normalized(),
                                        Eigen::Vector3d(0.2182, -0.8729, 0.4364).normalized(),
                                        Eigen::Vector3d(0.7071, 0.7071, 0.0),
                                        Eigen::Vector3d(-0.9487, -0.3162, 0.0)};
  int inside_votes = 0, votes = 0;
  for (const auto& direction : directions) {
    if (!closed_ && direction.z() != 0.0) continue;
    int crossings = 0;
    double t = 0.0;
    for (int guard = 0; guard < 1000; ++guard) {
      const RayHit hit = geometry_->intersect(point, direction, t + 1e-6);
      if (!hit.hit) break;
      ++crossings;
      t = hit.distance_m;
    }
    ++votes;
    if (crossings % 2 == 1) ++inside_votes;
  }
  return 2 * inside_votes > votes;
}

double AcousticScene::freeVolumeInSphereM3(const Eigen::Vector3d& centre, double radius_m) const {
  constexpr int kPoints = 16;  // per diameter
  const double step = 2.0 * radius_m / kPoints;
  int in_sphere = 0, inside = 0;
  for (int i = 0; i < kPoints; ++i) {
    for (int j = 0; j < kPoints; ++j) {
      for (int k = 0; k < kPoints; ++k) {
        const Eigen::Vector3d offset = step * (Eigen::Vector3d(i, j, k) + Eigen::Vector3d::Constant(0.5)) -
                                       Eigen::Vector3d::Constant(radius_m);
        if (offset.squaredNorm() > radius_m * radius_m) continue;
        ++in_sphere;
        if (isInside(centre + offset)) ++inside;
      }
    }
  }
  // The share of the grid inside, times the sphere's exact volume: a sphere clear of
  // every wall comes out exact.
  const double sphere_m3 = 4.0 / 3.0 * 3.14159265358979323846 * radius_m * radius_m * radius_m;
  return in_sphere > 0 ? sphere_m3 * inside / in_sphere : 0.0;
}

void AcousticScene::requireInside(const Eigen::Vector3d& point, const std::string& what, double clearance_m) const {
  std::ostringstream where;
  where << what << " (" << point.x() << ", " << point.y() << ", " << point.z() << ") m";
  if (!point.allFinite()) throw InputError(where.str() + " is not a finite position");
  if (shape_) {
    if (!shape_->inBox(point)) {
      const Eigen::Vector3d& size = shape_->size_m;
      where << " is outside the room (its box spans [0, " << size.x() << "] x [0, " << size.y() << "] x [0, "
            << size.z() << "] m)";
      throw InputError(where.str());
    }
    if (const auto object = shape_->objectContaining(point)) {
      where << " is inside object " << *object << " (" << shape_->objects[*object].label << ")";
      throw InputError(where.str());
    }
  } else if (!isInside(point)) {
    throw InputError(where.str() + " is outside the room or inside an object or wall");
  }
  // Clearance: no surface closer than clearance_m along a spread of directions.
  for (int i = 0; i < 27; ++i) {
    const Eigen::Vector3d d(i % 3 - 1, (i / 3) % 3 - 1, (i / 9) % 3 - 1);
    if (d.isZero()) continue;
    const RayHit hit = geometry_->intersect(point, d.normalized(), 0.0, clearance_m);
    if (hit.hit) throw InputError(where.str() + " is closer than " + std::to_string(clearance_m) + " m to a surface");
  }
}

}  // namespace room_reverb::core
