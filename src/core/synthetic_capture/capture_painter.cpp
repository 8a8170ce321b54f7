#include "capture_painter.h"

#include <algorithm>
#include <cmath>

#include "value_noise.h"

namespace room_reverb::core::capture_detail {
namespace {

void addOnce(std::vector<std::string>& names, const std::string& name) {
  if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
}

// A clear sky, paler towards the horizon; only seen through an open top, at infinity,
// so both cameras see the same.
Rgb skyColor(const Eigen::Vector3d& direction) {
  const double up = std::sqrt(std::clamp(direction.z(), 0.0, 1.0));
  return Rgb(200, 220, 236) + (Rgb(92, 142, 206) - Rgb(200, 220, 236)) * up;
}

}  // namespace

std::vector<std::string> captureMaterialNames(const RoomModel& room) {
  std::vector<std::string> names;
  for (const char* face : kRoomSurfaceNames) {
    if (!room.has_ceiling && std::string(face) == "ceiling") continue;
    const auto it = room.surfaces.find(face);
    if (it != room.surfaces.end()) addOnce(names, it->second.material);
  }
  for (const CuboidObject& object : room.objects) addOnce(names, object.material);
  return names;
}

namespace {

double unitFraction(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-53; }

// One photograph of the look's family, or none (the drawn texture), from `salt` alone, so
// that a material looks the same in both cameras and in every capture with the seed.
void choosePhoto(MaterialLook& look, const PhotoTextureSet& set, double share, std::uint64_t salt) {
  // Suspended ceiling tiles (0.6 m mineral-fibre panels in a grid) share the tiles family
  // with floor and wall tiles but not their look, and no collection has a photograph of
  // them: they stay drawn rather than be painted as a terracotta floor.
  if (look.large_tiles) return;
  const auto candidates = set.ofFamily(look.family);
  if (candidates.empty() || unitFraction(hashCombine(salt, 1)) >= share) return;
  const std::size_t pick = hashCombine(salt, 2) % candidates.size();
  look.photo = candidates[pick];
  // A photograph's listed width is an estimate from its content (brick courses, planks);
  // 0.75..1.33 of it covers that doubt and the spread of real sizes.
  look.photo_width_m = look.photo->width_m * std::pow(4.0 / 3.0, 2.0 * unitFraction(hashCombine(salt, 3)) - 1.0);
  // A white balance and paint shade of its own: up to +-15 % per channel, so that one
  // photograph does not teach one exact colour.
  for (int c = 0; c < 3; ++c) look.tint[c] = 0.85 + 0.3 * unitFraction(hashCombine(salt, 4 + static_cast<std::uint64_t>(c)));
}

}  // namespace

CapturePainter makeCapturePainter(const RoomModel& room, const MaterialLibrary& library,
                                  const CaptureOptions& options, const std::vector<std::string>& material_names) {
  const MaterialLibrary materials = materialsFor(room, library);
  auto canonical = [&](const std::string& name) { return materials.get(name).name; };
  std::vector<std::string> flat;
  for (const std::string& name : options.low_texture_materials) flat.push_back(canonical(name));

  CapturePainter painter;
  painter.geometry = makeCaptureGeometry(room, material_names);
  for (const std::string& name : material_names) {
    const std::string key = canonical(name);
    const bool poorly_textured = std::find(flat.begin(), flat.end(), key) != flat.end();
    MaterialLook look = makeMaterialLook(key, poorly_textured ? options.low_texture_contrast : 1.0);
    if (options.photo_textures) choosePhoto(look, *options.photo_textures, options.photo_share, hashCombine(options.seed, nameHash(key)));
    painter.looks.push_back(std::move(look));
  }
  const auto& emitters = options.camera.emitter_labels;
  for (const CuboidObject& object : room.objects) {
    painter.emits.push_back(std::find(emitters.begin(), emitters.end(), object.label) != emitters.end());
  }
  painter.emitted = options.camera.emitter_grey * Rgb(1.0, 0.97, 0.9);
  painter.seed = options.seed;
  painter.shading = options.shading;
  painter.sunlight = !room.has_ceiling;
  if (painter.sunlight) {
    painter.light_m = Eigen::Vector3d(0.4, 0.3, 0.87).normalized();
  } else {
    painter.light_m = Eigen::Vector3d(0.5 * room.size_m.x(), 0.5 * room.size_m.y(),
                                      std::max(0.5 * room.size_m.z(), room.size_m.z() - 0.25));
    // Far corners dimmer, but never black: half intensity at 60 % of the room diagonal.
    painter.falloff_distance_m = 0.6 * room.size_m.norm();
  }
  return painter;
}

Rgb paintHit(const CapturePainter& painter, const Eigen::Vector3d& direction, const SurfaceHit& hit,
             double sample_angle_rad) {
  if (hit.sky) return skyColor(direction);
  if (hit.object_id >= kCaptureFirstObjectId) {
    const std::size_t k = hit.object_id - kCaptureFirstObjectId;
    if (k < painter.emits.size() && painter.emits[k]) return painter.emitted;
  }
  // Grazing views stretch a sample along the surface; capped so far floors still filter
  // to a finite (if coarse) footprint.
  const double cos_view = std::max(std::abs(direction.dot(hit.normal)), 0.15);
  SurfaceSample sample;
  sample.s_m = hit.s_m;
  sample.t_m = hit.t_m;
  sample.salt = hashCombine(hashCombine(painter.seed, hit.object_id), static_cast<std::uint64_t>(hit.face));
  sample.footprint_m = sample_angle_rad * hit.distance_m / cos_view;
  const Rgb albedo = textureColor(painter.looks[static_cast<std::size_t>(hit.material)], sample);
  if (!painter.shading) return albedo;

  double diffuse = 0.0;
  if (painter.sunlight) {
    diffuse = std::max(0.0, hit.normal.dot(painter.light_m));
  } else {
    const Eigen::Vector3d to_light = painter.light_m - hit.point_m;
    const double distance = to_light.norm();
    const double ratio = distance / painter.falloff_distance_m;
    diffuse = distance > 0.0 ? std::max(0.0, hit.normal.dot(to_light) / distance) / (1.0 + ratio * ratio) : 0.0;
  }
  const double shade = painter.ambient + (1.0 - painter.ambient) * diffuse;
  return albedo * shade;
}

}  // namespace room_reverb::core::capture_detail
