// room_reverb room-model: the visual route on files. A vertical stereo pair of 360°
// images -> spherical depth -> point cloud -> room model of labelled cuboids with
// materials, written as the room.yaml that `room_reverb simulate --room` reads.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <opencv2/imgproc.hpp>

#include "arguments.h"
#include "command.h"
#include "depth_input.h"
#include "image_files.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/common/error.h"
#include "room_reverb/vision/capture_ingest.h"
#include "room_reverb/vision/material_overrides.h"
#include "room_reverb/vision/visual_route.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelp = R"(usage: room_reverb room-model --top TOP.png (--bottom BOTTOM.png | --depth FILE) --out ROOM.yaml
                              [--baseline M] [--fisheye] [--calibration FILE] [--width W]
                              [--leveling image|none] [--cloud CLOUD.pcd] [--range RANGE.tiff]
                              [--materials-override FILE.yaml] [--no-relief]
                              [--no-range-correction] [--no-rectification]

The paper's visual route on a capture from two vertically aligned 360° cameras: spherical
stereo along the image columns, the point cloud in the rig frame, the room box (walls,
floor, ceiling if any) and furniture cuboids fitted to it, and a material for each from
its colour and texture. The images are equirectangular (2:1, the upper camera's as TOP),
or dual-fisheye with --fisheye. `room_reverb make-capture` renders test pairs.

  --top FILE, --bottom FILE   the upper and lower camera's images (same size)
  --depth FILE                depth from elsewhere instead of the bottom image and the
                              stereo: a range image (.tif/.tiff, 32-bit float metres from the
                              top camera on the top image's grid, NaN where invalid, as
                              --range writes) or a point cloud (.pcd, metres, rig frame)
  --out FILE                  the room model (room.yaml of DESIGN.md)
  --baseline M                vertical distance between the camera centres [m]; default 0.2
  --fisheye                   the images are dual-fisheye (2S x S); stitched first
  --calibration FILE          dual-fisheye calibration (default config/dual_fisheye.yaml)
  --width W                   equirect width to work at [px], even; default the input's
                              (2 S for dual fisheye)
  --leveling MODE             image (default): the pair is turned about the baseline to the
                              room's walls and the rig's tilt found from the images' straight
                              edges, then taken out of the cloud; none: the rig stood upright
  --cloud FILE                also write the point cloud (binary PCD, rig frame)
  --range FILE                also write the top camera's range image (32-bit float TIFF,
                              metres, NaN where invalid)
  --materials-override FILE   materials you know better than the camera (YAML):
                                surfaces: {floor: linoleum_on_concrete, wall_y_max: brick_bare}
                                objects: [{index: 3, material: wood_panel},
                                          {label: sofa, material: fabric_upholstered_seat}]
                              names from config/materials.yaml; an overridden face or object
                              gets confidence 1 (see docs/visual-route.md)
  --no-relief                 plain faces: no relief scattering from what the cloud shows
                              standing on the faces or inside the objects' boxes (by default
                              each gets one, as relief_scattering in the model)
  --no-range-correction       ranges as the depth gives them; by default a disparity
                              offset of the stereo on which the floor and the ceiling agree
                              (2 mrad or more the same everywhere, 1 mrad or more with the
                              azimuth as a tilted camera gives it) is found from how they
                              bend and every range corrected for it, with a warning saying
                              by how much
  --no-rectification          the pair as it comes; by default the bottom camera's turn
                              against the top one (1 mrad or more) is found from features
                              matched between the images and the bottom image turned to
                              face as the top one does, with a warning saying by how much

Prints the room's size, the objects, each face's and object's material with its
confidence and runner-up (the next likeliest) and its relief (the share of its seen area
off its plane and the scattering that gives at 500 Hz / 1 kHz / 2 kHz), where a close vote fell back to the
commonest material of the kind and where the override file replaced what was found, and
the time of each step.
Exit status: 0 on success, 2 with one line on stderr for bad input (unreadable or
mismatched images, images that are not 2:1, black or saturated, a baseline that is not
positive, depth of the wrong type or size, a capture that shows no room, an override file
that is missing, malformed or names an unknown face, material, index or label). What a user
should check (a wall placed without a plane of its own, an open side, levelling by the
cloud where the images show too few straight edges) is printed as "warning:" lines on
stderr.
)";

cv::Mat readCameraImage(const std::string& path) {
  cv::Mat image = readImage(path);
  if (image.depth() != CV_8U) throw InputError(path + ": needs an 8-bit image (got another bit depth)");
  if (image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2BGR);
  return image;
}

// How a material was chosen, after its name: confidence, runner-up, fallback, override.
std::string materialNote(const SurfaceMaterialDecision& d, double confidence) {
  std::ostringstream out;
  out << " (confidence " << confidence;
  if (d.overridden) {
    out << "; override, the route found " << d.found_material << " at " << d.found_confidence;
  } else {
    if (!d.runner_up.empty()) out << "; runner-up " << d.runner_up << " " << d.runner_up_confidence;
    if (d.fell_back) out << "; fallback: " << d.fallback_reason;
    if (d.joint_grid) out << "; tiles: " << d.joint_grid_reason;
    if (!d.seen && d.family != TextureFamily::kOpening) out << "; not seen";
  }
  out << ")";
  return out.str();
}

// The relief a face was given: what was seen of it and the scattering at 500 Hz-2 kHz.
std::string reliefNote(const ReliefEstimate& relief) {
  std::ostringstream out;
  out << std::setprecision(2) << "relief: " << 100.0 * relief.relief_share << " % of " << relief.seen_m2
      << " m^2 seen off its plane(s), rms " << relief.rms_height_m << " m; scattering " << relief.scattering[3] << " / "
      << relief.scattering[4] << " / " << relief.scattering[5] << " at 500 Hz / 1 kHz / 2 kHz";
  return out.str();
}

void printRoom(const RoomLayout& layout, const std::vector<SurfaceMaterialDecision>& decisions, const VisualRouteTimes& t,
               std::size_t points) {
  const RoomModel& m = layout.model;
  std::cout << "room " << m.size_m.x() << " x " << m.size_m.y() << " x " << m.size_m.z() << " m"
            << (m.has_ceiling ? "" : " (no ceiling)") << ", rig at (" << m.rig_position_m.transpose()
            << ") m, yaw " << layout.rig_yaw_rad * 180.0 / M_PI << " deg, " << points << " points\n";
  // Decisions come faces first (kRoomSurfaceNames order, without a missing ceiling), then
  // objects in the model's order.
  std::size_t next = 0;
  for (std::size_t f = 0; f < kRoomSurfaceNames.size(); ++f) {
    const char* name = kRoomSurfaceNames[f];
    const auto it = m.surfaces.find(name);
    if (it == m.surfaces.end()) continue;
    std::cout << "  " << name << ": " << it->second.material;
    if (next < decisions.size() && decisions[next].name == name) {
      std::cout << materialNote(decisions[next++], it->second.confidence) << "\n";
    } else {
      std::cout << " (confidence " << it->second.confidence << ")\n";
    }
    const ReliefEstimate& relief = layout.face_relief[f];
    if (relief.estimated) std::cout << "    " << reliefNote(relief) << "\n";
  }
  for (std::size_t k = 0; k < m.objects.size(); ++k) {
    const CuboidObject& o = m.objects[k];
    std::cout << "  object " << o.label << ": " << o.size_m.x() << " x " << o.size_m.y() << " x " << o.size_m.z()
              << " m at (" << o.center_m.transpose() << "), " << o.material;
    if (next < decisions.size()) {
      std::cout << materialNote(decisions[next++], o.confidence) << "\n";
    } else {
      std::cout << " (confidence " << o.confidence << ")\n";
    }
    if (k < layout.object_relief.size() && layout.object_relief[k].estimated) {
      std::cout << "    " << reliefNote(layout.object_relief[k]) << "\n";
    }
  }
  std::cout << "time: stereo " << t.stereo_s << " s, cloud " << t.cloud_s << " s, range bias " << t.range_bias_s
            << " s, layout " << t.layout_s
            << " s, materials " << t.materials_s << " s, relief " << t.relief_s << " s\n";
}

int runRoomModel(const std::vector<std::string>& raw) {
  const Arguments args(raw,
                       {"top", "bottom", "depth", "out", "baseline", "calibration", "width", "leveling", "cloud", "range",
                        "materials-override"},
                       {"fisheye", "no-relief", "no-range-correction", "no-rectification"});
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  for (const char* required : {"top", "out"}) {
    if (!args.has(required)) throw UsageError(std::string("--") + required + " is required");
  }
  const bool depth_given = args.has("depth");
  if (depth_given == args.has("bottom")) throw UsageError("give either --bottom (stereo) or --depth, not both or neither");
  if (depth_given && args.has("range")) throw UsageError("--range writes the stereo's range; with --depth there is none");
  const double baseline = args.doubleValue("baseline", 0.2);
  if (!(baseline > 0.0) || !std::isfinite(baseline)) {
    throw InputError("--baseline must be a positive distance in metres (got " + args.value("baseline", "") + ")");
  }
  const std::string override_file = args.value("materials-override", "");
  if (args.has("materials-override") && override_file.empty()) {
    throw UsageError("--materials-override needs a file");
  }
  // Read once here as well, so that a mistake in the file is reported before the stereo's
  // seconds are spent; what depends on the room (indices, labels) is checked once it stands.
  if (!override_file.empty()) loadMaterialOverrides(override_file, MaterialLibrary::loadDefault());
  CaptureIngestOptions ingest;
  ingest.leveling = parseLevelingSource(args.value("leveling", "image"), "--leveling");
  if (ingest.leveling != LevelingSource::kNone && ingest.leveling != LevelingSource::kImage) {
    throw UsageError("--leveling takes image or none (an IMU's orientation is for the capture_ingest node)");
  }
  ingest.width = args.intValue("width", 0);
  // With --depth there is no second camera to rectify against.
  ingest.rectification.enabled = !depth_given && !args.has("no-rectification");
  if (args.has("fisheye")) {
    ingest.format = CaptureImageFormat::kDualFisheye;
    ingest.calibration = loadDualFisheyeCalibration(args.value("calibration", defaultDualFisheyeCalibrationPath()));
  } else if (args.has("calibration")) {
    throw UsageError("--calibration is only used with --fisheye");
  }
  const cv::Mat top = readCameraImage(args.value("top", ""));
  // With --depth there is no bottom image: the top one stands in for it (the levelling
  // pools both images' straight edges; the same image twice gives the same frame).
  const IngestedCapture pair =
      ingestCapture(top, depth_given ? top : readCameraImage(args.value("bottom", "")), ingest);
  VisualRouteOptions options;
  loadDefaultMaterialModels(options);
  options.materials.override_file = override_file;
  options.relief.enabled = !args.has("no-relief");
  options.disparity_offset.enabled = !args.has("no-range-correction");
  options.level_from_cloud = pair.level_from_cloud;
  VisualRoute route;
  if (depth_given) {
    route.cloud = cloudFromDepthFile(args.value("depth", ""), pair.top, baseline, pair.leveling.image_rotation);
    route.layout = roomLayoutFromCloud(route.cloud, pair.top, baseline, options, pair.leveling.tilt, &route.times,
                                       &route.materials);
  } else {
    route = runVisualRoute(pair.top, pair.bottom, baseline, options, pair.leveling.tilt);
  }
  saveRoomModel(args.value("out", ""), route.layout.model);
  if (args.has("cloud")) savePointCloudPcd(args.value("cloud", ""), route.cloud);
  if (args.has("range")) writeImage(args.value("range", ""), route.depth.range_m);
  // What happened on the way, once the room stands: a refusal stays one line.
  if (pair.manhattan) {
    std::cout << "levelled: turned " << pair.leveling.yaw_rad * 180.0 / M_PI << " deg about the baseline, rig tilt "
              << pair.leveling.tilt_rad * 180.0 / M_PI << " deg (" << pair.manhattan->segments << " line segments)\n";
  }
  for (const std::string& warning : pair.warnings) std::cerr << "warning: " << warning << "\n";
  for (const std::string& warning : route.layout.warnings) std::cerr << "warning: " << warning << "\n";
  printRoom(route.layout, route.materials, route.times, route.cloud.points.size());
  std::cout << "wrote " << args.value("out", "") << "\n";
  return 0;
}

const CommandRegistration registration({"room-model", "room model (cuboids, materials) from a 360° stereo pair",
                                        kHelp, runRoomModel});

}  // namespace
}  // namespace room_reverb::tool
