// room_reverb make-capture: a synthetic stereo 360° capture of a scene, with its truth
// (range, material and object per pixel), for developing and testing the visual route.
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "arguments.h"
#include "command.h"
#include "image_files.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/synthetic_capture/capture_generator.h"
#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/vision/dual_fisheye.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelp = R"(usage: room_reverb make-capture --scene SCENE.yaml --out DIR [--width 2048] [--seed N]
                                [--noise SIGMA] [--no-shading] [--fisheye] [--baseline M]
                                [--supersampling N] [--calibration FILE] [--threads N]

Renders what two vertically aligned 360° cameras at the scene's rig pose would capture:
exact ray casting of the room box and its objects with procedural textures per material.
The scene is a room model (room.yaml format; rig_in_room is the rig) with an optional
capture: section (include/room_reverb/synthetic_capture/capture_scene.h); options here override it.
Examples: data/captures/*.yaml.

  --scene FILE          the capture scene
  --out DIR             output folder (created if missing)
  --width W             equirect width in pixels, even, >= 64 (height W/2); default 2048
  --seed N              textures and noise (same seed, same bytes); default 1
  --noise SIGMA         Gaussian sensor noise in grey levels; default 0
  --no-shading          flat texture colours (no light)
  --fisheye             also write the dual-fisheye images (2S x S, S = W/2)
  --calibration FILE    dual-fisheye calibration (default config/dual_fisheye.yaml)
  --baseline M          vertical distance between the camera centres [m]; default 0.2
  --supersampling N     N x N samples per pixel (antialiasing); default 2
  --threads N           worker threads (0: all cores); the result does not depend on it

Writes to DIR, for CAM = top and bottom: CAM.png (colour, equirect), CAM_range.tiff
(32-bit float metres from the camera centre, inf for sky), CAM_material.png and
CAM_object.png (16-bit ids, 65535 sky), CAM_fisheye.png with --fisheye, and scene.yaml
(the scene as rendered, with the id -> name lists and the camera centres).
Exit status: 0 on success, 2 with one line on stderr for bad input.
)";

std::uint64_t seedValue(const Arguments& args, std::uint64_t fallback) {
  if (!args.has("seed")) return fallback;
  const std::string text = args.value("seed", "");
  char* end = nullptr;
  const unsigned long long seed = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || text.front() == '-') throw UsageError("--seed needs a whole number >= 0, got '" + text + "'");
  return seed;
}

int runMakeCapture(const std::vector<std::string>& raw) {
  const Arguments args(raw, {"scene", "out", "width", "seed", "noise", "baseline", "supersampling", "calibration", "threads"},
                       {"no-shading", "fisheye"});
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  if (!args.has("scene")) throw UsageError("--scene SCENE.yaml is required");
  if (!args.has("out")) throw UsageError("--out DIR is required");

  CaptureScene scene = loadCaptureScene(args.value("scene", ""));
  CaptureOptions& options = scene.options;
  options.width = args.intValue("width", options.width);
  options.seed = seedValue(args, options.seed);
  options.noise_sigma = args.doubleValue("noise", options.noise_sigma);
  options.baseline_m = args.doubleValue("baseline", options.baseline_m);
  options.supersampling = args.intValue("supersampling", options.supersampling);
  options.threads = args.intValue("threads", options.threads);
  if (args.has("no-shading")) options.shading = false;
  if (args.has("fisheye")) options.fisheye = true;
  if (options.fisheye) {
    options.fisheye_calibration = loadDualFisheyeCalibration(args.value("calibration", defaultDualFisheyeCalibrationPath()));
  } else if (args.has("calibration")) {
    throw UsageError("--calibration is only used with --fisheye");
  }
  const MaterialLibrary library = MaterialLibrary::loadDefault();
  validateCapture(scene.room, library, options);  // before touching the output folder

  const std::filesystem::path out = args.value("out", "");
  createFolder(out.string());

  const StereoCapture capture = renderCapture(scene.room, library, options);
  for (const auto& [name, camera] : {std::pair<const char*, const CameraCapture*>{"top", &capture.top}, {"bottom", &capture.bottom}}) {
    const std::string cam = name;
    writeImage((out / (cam + ".png")).string(), camera->color);
    writeImage((out / (cam + "_range.tiff")).string(), camera->range_m);
    writeImage((out / (cam + "_material.png")).string(), camera->material_id);
    writeImage((out / (cam + "_object.png")).string(), camera->object_id);
    if (!camera->fisheye.empty()) writeImage((out / (cam + "_fisheye.png")).string(), camera->fisheye);
  }
  saveCaptureScene((out / "scene.yaml").string(), scene, &capture);
  std::cout << "wrote " << out.string() << ": top and bottom " << options.width << " x " << options.width / 2
            << " equirect" << (options.fisheye ? " and dual-fisheye" : "") << " images, baseline " << options.baseline_m
            << " m, " << capture.material_names.size() << " materials, " << scene.room.objects.size() << " objects\n";
  return 0;
}

const CommandRegistration registration({"make-capture", "render a synthetic stereo 360° capture of a scene, with truth",
                                        kHelp, runMakeCapture});

}  // namespace
}  // namespace room_reverb::tool
