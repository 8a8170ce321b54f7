// Photographic textures for the capture generator: the bundled set, its loader's errors,
// sampling (pixel values, wrapping, filtering far away), captures painted with them, the
// scene file's keys, and training samples restricted to the families a collection holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "room_reverb/common/error.h"
#include "room_reverb/synthetic_capture/capture_generator.h"
#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/synthetic_capture/material_training.h"
#include "room_reverb/synthetic_capture/photo_textures.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;
using room_reverb::test::tempPath;
using room_reverb::test::writeFile;

namespace {

const char* kHeader = "file,family,width_m,source,licence,origin\n";

const MaterialLibrary& library() {
  static const MaterialLibrary lib = MaterialLibrary::loadDefault();
  return lib;
}

// An image of saturated red and blue vertical stripes, 4 pixels each, 32 x 32.
std::string writeStripes(const std::string& name) {
  cv::Mat image(32, 32, CV_8UC3);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      image.at<cv::Vec3b>(y, x) = (x / 4) % 2 ? cv::Vec3b(220, 30, 30) : cv::Vec3b(30, 30, 220);  // BGR
    }
  }
  const std::string path = tempPath(name).string();
  cv::imwrite(path, image);
  return path;
}

// A CSV of one stripes photograph of `family` from collection `source`.
std::string writeStripeSet(const std::string& csv_name, const std::string& family, const std::string& source) {
  writeStripes("stripes.png");
  return writeFile(csv_name, std::string(kHeader) + "stripes.png," + family + ",0.4," + source + ",CC0,made by the test\n");
}

double saturatedShare(const cv::Mat& bgr, const cv::Mat& mask) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  int saturated = 0;
  const int total = cv::countNonZero(mask);
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      if (mask.at<unsigned char>(y, x) && hsv.at<cv::Vec3b>(y, x)[1] > 110) ++saturated;
    }
  }
  return total > 0 ? static_cast<double>(saturated) / total : 0.0;
}

}  // namespace

TEST(PhotoTextures, BundledSetHasThreeCollectionsAndARecordForEveryPhotograph) {
  const PhotoTextureSet set = loadPhotoTextures(defaultPhotoTexturePath());
  EXPECT_EQ(set.sources(), (std::vector<std::string>{"gimp", "sweethome3d", "ufoai"}));
  EXPECT_GE(set.textures.size(), 120u);
  std::set<TextureFamily> families;
  for (const auto& texture : set.textures) {
    families.insert(texture->family);
    EXPECT_FALSE(texture->licence.empty()) << texture->file;
    EXPECT_GE(texture->levels.front().cols, 32) << texture->file;
    EXPECT_GT(texture->width_m, 0.05) << texture->file;
  }
  // The families a room's box and furniture mostly show are covered by photographs.
  for (const TextureFamily family : {TextureFamily::kPlaster, TextureFamily::kBrick, TextureFamily::kWood, TextureFamily::kCarpet,
                                     TextureFamily::kTiles, TextureFamily::kConcrete, TextureFamily::kFabric, TextureFamily::kMetal}) {
    EXPECT_TRUE(families.count(family)) << toString(family);
  }
  const PhotoTextureSet others = set.withoutSources({"sweethome3d"});
  const PhotoTextureSet only = set.onlySources({"sweethome3d"});
  EXPECT_EQ(others.textures.size() + only.textures.size(), set.textures.size());
  EXPECT_EQ(only.sources(), std::vector<std::string>{"sweethome3d"});
}

TEST(PhotoTextures, SamplingReadsPixelsWrapsAndFiltersFarAway) {
  const PhotoTextureSet set = loadPhotoTextures(writeStripeSet("sampling.csv", "fabric", "test"));
  const PhotoTexture& stripes = *set.textures.front();
  ASSERT_EQ(stripes.levels.front().cols, 32);
  const double pixel = 0.4 / 32;
  // The centre of pixel column 1 (red) and 5 (blue), close up.
  const Eigen::Array3d red = photoTextureColor(stripes, 0.4, 1.5 * pixel, -0.5 * pixel, 0.0);
  const Eigen::Array3d blue = photoTextureColor(stripes, 0.4, 5.5 * pixel, -0.5 * pixel, 0.0);
  EXPECT_NEAR(red[0], 220.0, 1e-3);
  EXPECT_NEAR(red[2], 30.0, 1e-3);
  EXPECT_NEAR(blue[2], 220.0, 1e-3);
  // One image width further along is the same point of the tiling.
  const Eigen::Array3d wrapped = photoTextureColor(stripes, 0.4, 0.4 + 1.5 * pixel, -0.5 * pixel, 0.0);
  EXPECT_NEAR((wrapped - red).abs().maxCoeff(), 0.0, 1e-3);
  // From far away (a footprint of 8 pixels) the stripes blend towards their mean.
  const Eigen::Array3d far = photoTextureColor(stripes, 0.4, 1.5 * pixel, -0.5 * pixel, 8 * pixel);
  EXPECT_NEAR(far[0], 125.0, 20.0);
  EXPECT_NEAR(far[2], 125.0, 20.0);
  EXPECT_NEAR(stripes.mean_rgb[0], 125.0, 1.0);
}

TEST(PhotoTextures, ACapturePaintsTheFamilysPhotographOnItsSurfaces) {
  RoomModel room;
  room.size_m = {5.0, 4.0, 3.0};
  for (const char* face : kRoomSurfaceNames) room.surfaces[face] = {"plaster_smooth", 1.0};
  room.surfaces["floor"] = {"concrete_unpainted", 1.0};
  room.rig_position_m = {2.0, 1.5, 1.4};
  CaptureOptions options;
  options.width = 256;
  options.supersampling = 1;
  options.shading = false;
  options.photo_textures = std::make_shared<const PhotoTextureSet>(loadPhotoTextures(writeStripeSet("paint.csv", "plaster", "test")));
  const StereoCapture painted = renderCapture(room, library(), options);
  const auto plaster_id = static_cast<std::uint16_t>(
      std::find(painted.material_names.begin(), painted.material_names.end(), "plaster_smooth") - painted.material_names.begin());
  const cv::Mat walls = painted.top.material_id == plaster_id;
  const cv::Mat floor = painted.top.material_id != plaster_id;
  // The plaster surfaces show the saturated stripes; the concrete floor keeps its drawn grey.
  EXPECT_GT(saturatedShare(painted.top.color, walls), 0.8);
  EXPECT_LT(saturatedShare(painted.top.color, floor), 0.05);
  // The same seed paints the same bytes; no photographs (share 0) paints the drawn plaster.
  EXPECT_EQ(cv::norm(renderCapture(room, library(), options).top.color, painted.top.color, cv::NORM_INF), 0.0);
  options.photo_share = 0.0;
  EXPECT_LT(saturatedShare(renderCapture(room, library(), options).top.color, walls), 0.05);
  options.photo_share = 1.5;
  expectInputError([&] { renderCapture(room, library(), options); }, {"photo_share", "[0, 1]"});
}

TEST(PhotoTextures, BadListsAreOneLineInputErrors) {
  writeStripes("ok.png");
  writeFile("not_an_image.png", "plain text");
  const std::string row = "ok.png,brick,0.5,test,CC0,x\n";
  expectInputError([&] { loadPhotoTextures(tempPath("missing.csv").string()); }, {"missing.csv", "no such file"});
  expectInputError([&] { loadPhotoTextures(writeFile("empty.csv", "")); }, {"empty.csv", "header"});
  expectInputError([&] { loadPhotoTextures(writeFile("header.csv", "file,family\n" + row)); }, {"header.csv line 1", "header"});
  expectInputError([&] { loadPhotoTextures(writeFile("fields.csv", std::string(kHeader) + "ok.png,brick,0.5,test\n")); },
                   {"fields.csv line 2", "expected 6 fields", "got 4"});
  expectInputError([&] { loadPhotoTextures(writeFile("family.csv", std::string(kHeader) + "ok.png,marble,0.5,test,CC0,x\n")); },
                   {"family.csv line 2", "unknown texture family 'marble'"});
  for (const std::string width : {"abc", "-1", "0", "1.5m", "nan"}) {
    expectInputError([&] { loadPhotoTextures(writeFile("width.csv", std::string(kHeader) + "ok.png,brick," + width + ",test,CC0,x\n")); },
                     {"width.csv line 2", "width_m '" + width + "'"});
  }
  expectInputError([&] { loadPhotoTextures(writeFile("source.csv", std::string(kHeader) + "ok.png,brick,0.5,,CC0,x\n")); },
                   {"source.csv line 2", "source"});
  expectInputError([&] { loadPhotoTextures(writeFile("gone.csv", std::string(kHeader) + "gone.png,brick,0.5,test,CC0,x\n")); },
                   {"gone.png", "no such file", "gone.csv line 2"});
  expectInputError([&] { loadPhotoTextures(writeFile("text.csv", std::string(kHeader) + "not_an_image.png,brick,0.5,test,CC0,x\n")); },
                   {"not_an_image.png", "not a readable image", "text.csv line 2"});
  const PhotoTextureSet set = loadPhotoTextures(writeFile("good.csv", std::string(kHeader) + row));
  expectInputError([&] { set.onlySources({"elsewhere"}); }, {"no collection named 'elsewhere'", "test"});
}

TEST(PhotoTextures, SceneFilesNameTheSetItsCollectionsAndShare) {
  writeStripeSet("scene_set.csv", "brick", "test");
  const std::string room =
      "frame: room\nroom_box: {size_m: [4, 3, 2.5]}\n"
      "surfaces:\n  floor: {material: carpet}\n  ceiling: {material: plaster_smooth}\n  wall_x_min: {material: brick_bare}\n"
      "  wall_x_max: {material: brick_bare}\n  wall_y_min: {material: brick_bare}\n  wall_y_max: {material: brick_bare}\n"
      "rig_in_room: {position_m: [2, 1.5, 1.2], rotation_xyzw: [0, 0, 0, 1]}\n";
  const std::string path = writeFile("scene.yaml", room + "capture:\n  photo_textures: scene_set.csv\n  photo_sources: [test]\n  photo_share: 0.7\n");
  const CaptureScene scene = loadCaptureScene(path);
  ASSERT_TRUE(scene.options.photo_textures);
  EXPECT_EQ(scene.options.photo_textures->textures.size(), 1u);
  EXPECT_DOUBLE_EQ(scene.options.photo_share, 0.7);
  EXPECT_EQ(scene.photo_sources, std::vector<std::string>{"test"});
  // Written out, the scene still finds its photographs from another folder.
  const std::string copy = (tempPath("copy") / "scene.yaml").string();
  std::filesystem::create_directories(tempPath("copy"));
  saveCaptureScene(copy, scene);
  EXPECT_EQ(loadCaptureScene(copy).options.photo_textures->textures.size(), 1u);

  expectInputError([&] { loadCaptureScene(writeFile("bad_source.yaml", room + "capture:\n  photo_textures: scene_set.csv\n  photo_sources: [nowhere]\n")); },
                   {"bad_source.yaml", "capture.photo_sources", "no collection named 'nowhere'"});
  expectInputError([&] { loadCaptureScene(writeFile("no_set.yaml", room + "capture:\n  photo_sources: [test]\n")); },
                   {"no_set.yaml", "capture.photo_sources", "needs photo_textures"});
  expectInputError([&] { loadCaptureScene(writeFile("gone_set.yaml", room + "capture:\n  photo_textures: gone.csv\n")); },
                   {"gone.csv", "no such file"});
}

TEST(PhotoTextures, TrainingSamplesOnlyTheFamiliesAsked) {
  MaterialTrainingOptions options;
  options.patches_per_family = 4;
  options.max_rooms = 40;
  options.widths = {512};
  options.threads = 2;
  options.photo_textures = std::make_shared<const PhotoTextureSet>(loadPhotoTextures(defaultPhotoTexturePath()).onlySources({"gimp"}));
  options.photo_share = 1.0;
  options.families = {TextureFamily::kWood, TextureFamily::kBrick};
  const MaterialSamples samples = generateMaterialSamples(options, library());
  ASSERT_EQ(samples.families.size(), 8u);
  for (const TextureFamily family : samples.families) {
    EXPECT_TRUE(family == TextureFamily::kWood || family == TextureFamily::kBrick) << toString(family);
  }
  options.photo_share = 2.0;
  expectInputError([&] { generateMaterialSamples(options, library()); }, {"photo_share", "[0, 1]"});
}
