#include "room_reverb/acoustics/embree_scene.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <stdexcept>

namespace room_reverb::core {

struct EmbreeScene::Handles {
  RTCDevice device = nullptr;
  RTCScene watertight = nullptr;
  RTCScene fast = nullptr;
  ~Handles() {
    if (watertight) rtcReleaseScene(watertight);
    if (fast) rtcReleaseScene(fast);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

// The mesh in one BVH. Watertight: Embree's robust mode (its Plücker-coordinate test)
// lets no ray through a shared edge, which the FDTD grid's parity count along grid lines
// and a room model's leak check rely on; it builds with spatial splits
// (RTC_BUILD_QUALITY_HIGH), which change nothing measurable for it. The other uses
// Embree's Möller-Trumbore test, whose rays may slip between two triangles at their shared
// edge, and no spatial splits: with them its BVH traced BRAS CR2 8 % slower.
RTCScene buildScene(RTCDevice device, const TriangleMesh& mesh, bool watertight) {
  RTCScene scene = rtcNewScene(device);
  if (watertight) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, watertight ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
  }
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangleCount()));
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  return scene;
}
}  // namespace

EmbreeScene::EmbreeScene(TriangleMesh mesh) : mesh_(std::move(mesh)), handles_(std::make_unique<Handles>()) {
  validateMesh(mesh_, "scene mesh");
  handles_->device = rtcNewDevice(nullptr);
  if (!handles_->device) throw std::runtime_error("Embree: cannot create a device");
  handles_->watertight = buildScene(handles_->device, mesh_, true);
  handles_->fast = buildScene(handles_->device, mesh_, false);
  bounds_min_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  bounds_max_ = -bounds_min_;
  for (std::size_t i = 0; i < mesh_.vertices.size(); ++i) {
    bounds_min_ = bounds_min_.cwiseMin(mesh_.vertices[i]);
    bounds_max_ = bounds_max_.cwiseMax(mesh_.vertices[i]);
  }
  normals_.resize(mesh_.triangleCount());
  for (std::size_t t = 0; t < mesh_.triangleCount(); ++t) normals_[t] = mesh_.normal(t);
}

EmbreeScene::~EmbreeScene() = default;

namespace {

RayHit nearestHit(RTCScene scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_near, double t_far,
                  const std::vector<Eigen::Vector3d>& normals) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query{};
  query.ray.org_x = static_cast<float>(origin.x());
  query.ray.org_y = static_cast<float>(origin.y());
  query.ray.org_z = static_cast<float>(origin.z());
  query.ray.dir_x = static_cast<float>(direction.x());
  query.ray.dir_y = static_cast<float>(direction.y());
  query.ray.dir_z = static_cast<float>(direction.z());
  query.ray.tnear = static_cast<float>(t_near);
  query.ray.tfar = std::isinf(t_far) ? std::numeric_limits<float>::infinity() : static_cast<float>(t_far);
  query.ray.mask = 0xFFFFFFFFu;
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &context, &query);
  RayHit hit;
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.hit = true;
  hit.distance_m = query.ray.tfar;
  hit.triangle = query.hit.primID;
  hit.normal = normals[hit.triangle];
  return hit;
}

}  // namespace

RayHit EmbreeScene::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_near,
                              double t_far) const {
  return nearestHit(handles_->watertight, origin, direction, t_near, t_far, normals_);
}

RayHit EmbreeScene::intersectFast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_near) const {
  const RayHit hit = nearestHit(handles_->fast, origin, direction, t_near, std::numeric_limits<double>::infinity(), normals_);
  return hit.hit ? hit : intersect(origin, direction, t_near);
}

bool EmbreeScene::occluded(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double margin_m) const {
  const Eigen::Vector3d delta = to - from;
  const double length = delta.norm();
  if (length <= 2 * margin_m) return false;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  const Eigen::Vector3d direction = delta / length;
  ray.org_x = static_cast<float>(from.x());
  ray.org_y = static_cast<float>(from.y());
  ray.org_z = static_cast<float>(from.z());
  ray.dir_x = static_cast<float>(direction.x());
  ray.dir_y = static_cast<float>(direction.y());
  ray.dir_z = static_cast<float>(direction.z());
  ray.tnear = static_cast<float>(margin_m);
  ray.tfar = static_cast<float>(length - margin_m);
  ray.mask = 0xFFFFFFFFu;
  rtcOccluded1(handles_->watertight, &context, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0.0f;
}

}  // namespace room_reverb::core
