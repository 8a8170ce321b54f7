#pragma once
// Geometry plus physics: a mesh in an Embree BVH, each triangle's material resolved from a
// library (with the per-material absorption and scattering overrides the model allows),
// and the room's volume and surface.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/acoustics/diffraction_scattering.h"
#include "room_reverb/acoustics/embree_scene.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/acoustics/room_shape.h"

namespace room_reverb::core {

struct MaterialOverrides {
  // Replaces the absorption of the named material (by its name in the mesh).
  std::map<std::string, OctaveBandValues> absorption;
  // Replaces the scattering of the named material.
  std::map<std::string, OctaveBandValues> scattering;
  // One scattering coefficient for every surface and band (e.g. 0 to turn scattering off).
  std::optional<double> global_scattering;
};

// Triangles whose surface has a relief: their material's scattering is combined with
// `scattering` (relief_scattering.h) in a material of their own, named after the
// material and `surface` ("plaster_smooth, wall_x_min's relief"), after any override.
struct SurfaceRelief {
  std::string surface;
  std::vector<std::size_t> triangles;
  OctaveBandValues scattering{};
};

struct ScenePlane {
  Eigen::Vector3d normal;  // unit
  double offset = 0.0;     // plane: normal . x = offset
  std::vector<std::size_t> triangles;
};

class AcousticScene {
 public:
  // Throws InputError for an invalid mesh, an unknown material name, or an override out
  // of [0, 1]. `closed`: the room should hold every ray (rays that leave are leaks).
  // A global scattering override replaces the reliefs' too (every surface's scattering).
  AcousticScene(TriangleMesh mesh, const MaterialLibrary& library,
                const MaterialOverrides& overrides = {}, bool closed = true,
                const std::vector<SurfaceRelief>& reliefs = {});
  // A scene whose mesh is the triangles of `shape` (roomModelToScene): whether a point is
  // in the room, and the volume of a closed room, come from the solids, exactly, not from
  // the triangles. Closed when the shape has a ceiling.
  AcousticScene(TriangleMesh mesh, const MaterialLibrary& library, const MaterialOverrides& overrides,
                RoomShape shape, const std::vector<SurfaceRelief>& reliefs = {});

  // The same room whose nine bands stand for the `third`-th third of every octave (0
  // lower, 1 centre, 2 upper): each material's third-octave coefficients where it has
  // them (thirdOctaveMaterial; an override or a global scattering replaces the thirds as
  // it replaces the octave), and band centres 2^((third - 1) / 3) times the octaves'. It
  // shares this scene's geometry. A simulation in third octaves runs once per third.
  AcousticScene thirdOctaveBands(int third) const;
  // Whether any material has third-octave coefficients.
  bool hasThirdOctaveMaterials() const;
  // The centre frequency each band stands for (Hz): the octaves' exact centres, or a
  // third's (thirdOctaveBands). Air absorption and the scattering of finite surfaces are
  // evaluated there.
  const OctaveBandValues& bandCentresHz() const { return band_centres_hz_; }

  const EmbreeScene& geometry() const { return *geometry_; }
  const TriangleMesh& mesh() const { return geometry_->mesh(); }
  const AcousticMaterial& material(std::size_t triangle) const {
    return materials_[static_cast<std::size_t>(mesh().triangle_material[triangle])];
  }
  const std::vector<AcousticMaterial>& materials() const { return materials_; }
  // Coplanar triangles grouped (normals within 1e-4, offsets within 1 mm).
  const std::vector<ScenePlane>& planes() const { return planes_; }
  std::size_t planeOf(std::size_t triangle) const { return triangle_plane_[triangle]; }
  // The connected coplanar surface the triangle belongs to (diffraction_scattering.h).
  const SurfaceExtent& surfaceExtent(std::size_t triangle) const { return patches_[triangle_patch_[triangle]]; }
  bool closed() const { return closed_; }
  // The solids the scene was built from; null for a scene from a mesh file.
  const RoomShape* roomShape() const { return shape_ ? &*shape_ : nullptr; }

  // Enclosed volume (the room shape's free volume when it is closed; otherwise by the
  // divergence theorem, absolute value, meaningful for closed meshes) and total surface
  // area.
  double volumeM3() const { return volume_m3_; }
  double surfaceM2() const { return surface_m2_; }
  // Area-weighted mean absorption per band.
  OctaveBandValues meanAbsorption() const;

  // Whether `point` is inside the room and outside every object: from the room shape when
  // there is one, else by crossing parity along several rays (a majority decides).
  bool isInside(const Eigen::Vector3d& point) const;
  // InputError unless `point` is inside the room, outside every object and at least
  // `clearance_m` from every surface. With a room shape the message names the object that
  // holds the point ("listener (2, 1, 1) m is inside object 3 (cabinet)", numbered from 0
  // as in the model's list).
  void requireInside(const Eigen::Vector3d& point, const std::string& what, double clearance_m = 0.01) const;
  // The volume (m^3) of the part of the sphere about `centre` that lies inside the room
  // and outside every object: the sphere's volume times the share of a grid of 16 points
  // per diameter that isInside accepts (exact for a sphere clear of every surface).
  double freeVolumeInSphereM3(const Eigen::Vector3d& centre, double radius_m) const;
  // Distance (m) from `point` to the nearest point of any triangle.
  double distanceToNearestSurface(const Eigen::Vector3d& point) const;

 private:
  std::shared_ptr<const EmbreeScene> geometry_;
  OctaveBandValues band_centres_hz_{};
  int third_ = -1;  // the third of every octave the bands stand for; -1: whole octaves
  std::vector<AcousticMaterial> materials_;
  std::vector<ScenePlane> planes_;
  std::vector<std::size_t> triangle_plane_;
  std::vector<SurfaceExtent> patches_;
  std::vector<std::size_t> triangle_patch_;
  bool closed_;
  std::optional<RoomShape> shape_;
  double volume_m3_ = 0.0;
  double surface_m2_ = 0.0;
};

}  // namespace room_reverb::core
