#pragma once
// The visual route in one call (the paper's section 3): a vertical stereo pair of
// equirectangular images -> spherical depth -> point cloud -> room layout of labelled
// cuboids -> a material per face and object. What `room_reverb room-model` and the
// room_model node's ~build run; each step is its own header (spherical_stereo.h,
// depth_cloud.h, room_layout.h, surface_materials.h).
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "room_reverb/vision/cloud_leveling.h"
#include "room_reverb/vision/depth_cloud.h"
#include "room_reverb/vision/point_cloud.h"
#include "room_reverb/vision/range_bias.h"
#include "room_reverb/vision/room_layout.h"
#include "room_reverb/vision/spherical_stereo.h"
#include "room_reverb/vision/surface_materials.h"
#include "room_reverb/vision/surface_relief.h"

#include <memory>

namespace room_reverb::core {

struct VisualRouteOptions {
  SphericalStereoOptions stereo;
  DepthCloudOptions cloud;
  RoomLayoutOptions layout;
  SurfaceMaterialOptions materials;
  // Each face's and object's relief scattering from the cloud (layout.face_relief,
  // object_relief and the model's relief_scattering); needs layout.assign_points.
  SurfaceReliefOptions relief;
  // Level the cloud by its own floor and ceiling (vision/cloud_leveling.h) before the fit,
  // where the images could not (IngestedCapture::level_from_cloud); applied after `tilt`.
  bool level_from_cloud = false;
  CloudLevelingOptions cloud_leveling;
  // The stereo's disparity offset found from the floor's and ceiling's flatness and taken
  // out of every range before the fit (vision/range_bias.h), where it is clear.
  DisparityOffsetOptions disparity_offset;
  // The material classifier and the family -> material table. Null: the shipped ones
  // (config/material_classifier.yml.gz, config/material_families.yaml) are loaded on each
  // call; callers that build more than one room load them once (loadDefaultMaterialModels).
  std::shared_ptr<const MaterialClassifier> classifier;
  std::shared_ptr<const MaterialFamilyTable> families;
};

// Fills options.classifier and options.families with the shipped models (InputError if
// they cannot be read).
void loadDefaultMaterialModels(VisualRouteOptions& options);

struct VisualRouteTimes {
  double stereo_s = 0.0;     // pair -> range image
  double cloud_s = 0.0;      // range image -> point cloud
  double range_bias_s = 0.0; // the stereo's disparity offset from the floor and ceiling
  double layout_s = 0.0;     // cloud -> cuboids
  double materials_s = 0.0;  // cuboids -> materials
  double relief_s = 0.0;     // cloud and cuboids -> each face's and object's relief
};

struct VisualRoute {
  SphericalDepth depth;
  PointCloud cloud;
  RoomLayout layout;  // layout.model is a complete room model (every face and object has a material)
  std::vector<SurfaceMaterialDecision> materials;  // how each face's and object's material was chosen
  VisualRouteTimes times;
};

// The room model from a cloud in the rig frame and the top camera's colour image of the
// same pair (for the materials). `tilt` levels the rig frame (ImageLeveling::tilt of
// vision/image_leveling.h: the cloud is fitted as tilt * p, and the layout's room_from_rig
// and rig pose include it); identity for a rig standing upright. InputError as
// fitRoomLayout and the material step report them (no room in the cloud, an image that is
// not 2:1 8-bit) and for a tilt that is not a rotation.
RoomLayout roomLayoutFromCloud(const PointCloud& cloud, const cv::Mat& top_color, double baseline_m,
                               const VisualRouteOptions& options, const Eigen::Matrix3d& tilt = Eigen::Matrix3d::Identity(),
                               VisualRouteTimes* times = nullptr,
                               std::vector<SurfaceMaterialDecision>* materials = nullptr);

// The whole route. InputError for a pair the stereo refuses (sizes, not 2:1, black or
// saturated, a baseline that is not positive) and as roomLayoutFromCloud.
VisualRoute runVisualRoute(const cv::Mat& top, const cv::Mat& bottom, double baseline_m,
                           const VisualRouteOptions& options = {},
                           const Eigen::Matrix3d& tilt = Eigen::Matrix3d::Identity());

}  // namespace room_reverb::core
