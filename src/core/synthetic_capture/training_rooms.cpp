#include "training_rooms.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "room_reverb/vision/material_classifier.h"

namespace room_reverb::core::material_detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kBaseline = 0.2;

double uniform(std::mt19937_64& rng, double low, double high) { return std::uniform_real_distribution<double>(low, high)(rng); }
bool chance(std::mt19937_64& rng, double p) { return uniform(rng, 0.0, 1.0) < p; }

std::string randomMaterial(std::mt19937_64& rng, const std::vector<std::vector<std::string>>& by_family) {
  std::vector<std::size_t> families;
  for (std::size_t f = 0; f < by_family.size(); ++f) {
    if (!by_family[f].empty()) families.push_back(f);
  }
  const auto& names = by_family[families[std::uniform_int_distribution<std::size_t>(0, families.size() - 1)(rng)]];
  return names[std::uniform_int_distribution<std::size_t>(0, names.size() - 1)(rng)];
}

// True if a point is within `margin` of the object's box (in its own frame).
bool nearObject(const CuboidObject& object, const Eigen::Vector3d& point, double margin) {
  const Eigen::Vector3d local =
      Eigen::AngleAxisd(-object.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix() * (point - object.center_m);
  return (local.array().abs() < 0.5 * object.size_m.array() + margin).all();
}

// A cuboid standing on the floor (sometimes hung on a wall, as cabinets are), square to
// the walls or turned, kept inside the box.
CuboidObject randomObject(std::mt19937_64& rng, const RoomModel& room, const std::string& material) {
  CuboidObject object;
  object.label = "object";
  object.material = material;
  // From loudspeakers to wardrobes.
  const double height = std::min(uniform(rng, 0.15, 2.2), room.size_m.z() - 0.2);
  object.size_m = Eigen::Vector3d(uniform(rng, 0.15, 2.2), uniform(rng, 0.15, 1.2), height);
  object.yaw_rad = chance(rng, 0.5) ? 0.0 : uniform(rng, -0.5 * kPi, 0.5 * kPi);
  const double reach = 0.5 * object.size_m.head<2>().norm();  // plan radius, any yaw
  const double bottom = chance(rng, 0.15) ? uniform(rng, 0.8, std::max(0.8, room.size_m.z() - height - 0.1)) : 0.0;
  object.center_m = Eigen::Vector3d(uniform(rng, reach, std::max(reach, room.size_m.x() - reach)),
                                    uniform(rng, reach, std::max(reach, room.size_m.y() - reach)), bottom + 0.5 * height);
  return object;
}

}  // namespace

std::vector<std::vector<std::string>> libraryMaterialsByFamily(const MaterialLibrary& library) {
  std::vector<std::vector<std::string>> by_family(kTextureFamilyCount);
  for (const std::string& name : library.names()) {
    by_family[static_cast<std::size_t>(textureFamilyIndex(textureFamilyFor(name).family))].push_back(name);
  }
  return by_family;
}

TrainingRoom randomTrainingRoom(std::uint64_t seed, const std::vector<std::vector<std::string>>& materials_by_family) {
  std::mt19937_64 rng(seed);
  TrainingRoom t;
  RoomModel& room = t.room;
  room.has_ceiling = chance(rng, 0.85);
  // Courtyards are larger than rooms: their far walls are the blurred, distant surfaces
  // the classifier must also handle.
  room.size_m = room.has_ceiling
                    ? Eigen::Vector3d(uniform(rng, 3.0, 10.0), uniform(rng, 3.0, 10.0), uniform(rng, 2.3, 4.0))
                    : Eigen::Vector3d(uniform(rng, 5.0, 20.0), uniform(rng, 5.0, 20.0), uniform(rng, 3.0, 12.0));
  for (const char* face : kRoomSurfaceNames) {
    if (!room.has_ceiling && std::string(face) == "ceiling") continue;
    room.surfaces[face] = {randomMaterial(rng, materials_by_family), 1.0};
  }
  room.rig_position_m = Eigen::Vector3d(uniform(rng, 0.6, room.size_m.x() - 0.6), uniform(rng, 0.6, room.size_m.y() - 0.6),
                                        uniform(rng, 0.9, std::min(2.0, room.size_m.z() - 0.5)));
  room.rig_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(uniform(rng, -kPi, kPi), Eigen::Vector3d::UnitZ()));
  const int objects = std::uniform_int_distribution<int>(0, 5)(rng);
  for (int k = 0; k < objects; ++k) {
    const CuboidObject object = randomObject(rng, room, randomMaterial(rng, materials_by_family));
    // Keep both cameras clear of it (and a little more, so it does not fill the view).
    if (!nearObject(object, room.rig_position_m, 0.5 * kBaseline + 0.4)) room.objects.push_back(object);
  }

  CaptureOptions& options = t.options;
  options.seed = rng();
  options.noise_sigma = uniform(rng, 0.0, 3.0);
  options.shading = chance(rng, 0.9);
  options.baseline_m = kBaseline;
  // Now and then a surface painted so evenly that its texture nearly vanishes.
  for (const auto& [face, assignment] : room.surfaces) {
    if (chance(rng, 0.1)) options.low_texture_materials.push_back(assignment.material);
  }
  options.low_texture_contrast = uniform(rng, 0.02, 0.3);
  return t;
}

}  // namespace room_reverb::core::material_detail
