#include "room_reverb/acoustics/embree_scene.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <stdexcept>

namespace room_reverb::core {

struct EmbreeScene::Handles {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Handles() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

EmbreeScene::EmbreeScene(TriangleMesh mesh) : mesh_(std::move(mesh)), handles_(std::make_unique<Handles>()) {
  validateMesh(mesh_, "scene mesh");
  handles_->device = rtcNewDevice(nullptr);
  if (!handles_->device) throw std::runtime_error("Embree: cannot create a device");
  handles_->scene = rtcNewScene(handles_->device);
  // Robust traversal: rays grazing shared edges of the room's triangles must not slip
  // through the cracks (a leak the ray tracer would otherwise count as real).
  rtcSetSceneFlags(handles_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(handles_->scene, RTC_BUILD_QUALITY_HIGH);

  RTCGeometry geometry = rtcNewGeometry(handles_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh_.vertices.size()));
  bounds_min_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  bounds_max_ = -bounds_min_;
  for (std::size_t i = 0; i < mesh_.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh_.vertices[i][k]);
    bounds_min_ = bounds_min_.cwiseMin(mesh_.vertices[i]);
    bounds_max_ = bounds_max_.cwiseMax(mesh_.vertices[i]);
  }
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh_.triangleCount()));
  normals_.resize(mesh_.triangleCount());
  for (std::size_t t = 0; t < mesh_.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = static_cast<unsigned>(mesh_.triangles[t][k]);
    normals_[t] = mesh_.normal(t);
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(handles_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(handles_->scene);
}

EmbreeScene::~EmbreeScene() = default;

RayHit EmbreeScene::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                              double t_near, double t_far) const {
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
  rtcIntersect1(handles_->scene, &context, &query);
  RayHit hit;
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.hit = true;
  hit.distance_m = query.ray.tfar;
  hit.triangle = query.hit.primID;
  hit.normal = normals_[hit.triangle];
  return hit;
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
  rtcOccluded1(handles_->scene, &context, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0.0f;
}

}  // namespace room_reverb::core
