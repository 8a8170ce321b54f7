#pragma once
// Capture scene files (data/captures/*.yaml): a room model in the room.yaml format of
// DESIGN.md, whose rig_in_room is the camera rig's pose, plus an optional `capture:`
// section saying how to render it:
//
//   capture:
//     baseline_m: 0.2                 # vertical distance between the camera centres [m]
//     width: 2048                     # equirect width [px], even, >= 64
//     supersampling: 2                # n x n colour samples per pixel
//     seed: 1                         # textures and noise
//     shading: true                   # Lambert light near the ceiling plus ambient
//     noise_sigma: 0.0                # sensor noise [grey levels]
//     fisheye: false                  # also render dual-fisheye images
//     low_texture_materials: [sheetrock]   # materials drawn nearly flat
//     low_texture_contrast: 0.03      # their texture contrast (1 = normal)
//     photo_textures: default         # paint materials with photographs (photo_textures.h):
//                                     # `default` (data/textures/textures.csv) or a CSV path,
//                                     # relative to the scene file; absent: drawn textures
//     photo_sources: [sweethome3d]    # only these collections of the CSV (absent: all)
//     photo_share: 1.0                # chance that a material with photographs gets one
//     camera:                         # what the camera does (CameraImperfections); all off by default
//       through_lenses: false         # colour through the two fisheye lenses, stitched
//       lens_offset_m: 0.0            # each lens's centre ahead of the camera centre [m], 0..0.05
//       vignetting: 0.0               # share of light lost at 90 degrees off a lens's axis, [0, 1)
//       back_lens_gain: 1.0           # back lens brightness relative to the front
//       top_exposure: 1.0             # each camera's exposure gain
//       bottom_exposure: 1.0
//       bottom_white_balance: [1, 1, 1]   # bottom camera's R, G, B gains relative to the top
//       jpeg_quality: 0               # 0: none; 1..100
//       native_scale: 1               # recorded at this times the width, then shrunk (1..4)
//       emitter_labels: [light, window]   # objects that glow (lamps, windows with daylight)
//       emitter_grey: 400             # their brightness [grey levels], above 255 clips
//
// Every key is optional, with the CaptureOptions defaults. A rendered capture's scene file
// adds a `labels:` section (the material and object names of the id images, and the camera
// centres); reading ignores it.
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/synthetic_capture/capture_generator.h"

namespace room_reverb::core {

struct CaptureScene {
  RoomModel room;
  CaptureOptions options;  // options.photo_textures loaded from the two fields below
  std::string photo_textures;               // as written in the file ("default" or a path); empty: none
  std::vector<std::string> photo_sources;   // empty: every collection
};

// InputError naming the file and key for anything malformed (room model errors as
// loadRoomModel reports them).
CaptureScene loadCaptureScene(const std::string& path);
CaptureScene parseCaptureScene(const std::string& yaml_text, const std::string& source = "capture scene");
// The room model's YAML, the capture section, and with `rendered` the labels section.
std::string captureSceneToYaml(const CaptureScene& scene, const StereoCapture* rendered = nullptr);
void saveCaptureScene(const std::string& path, const CaptureScene& scene, const StereoCapture* rendered = nullptr);

}  // namespace room_reverb::core
