// The material step of the visual route: colour/texture features, the shipped material
// classifier on held-out generated patches, surface materials of generated captures
// given their true layout (the "material right on >= 80 % of the surface area"),
// bad inputs, and the two tables in config/.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <set>
#include <string>

#include "room_reverb/common/error.h"
#include "room_reverb/synthetic_capture/capture_scene.h"
#include "room_reverb/vision/material_families.h"
#include "room_reverb/vision/material_features.h"
#include "room_reverb/synthetic_capture/material_training.h"
#include "room_reverb/vision/surface_materials.h"
#include "room_reverb/vision/surface_patches.h"
#include "room_reverb/vision/texture_family.h"
#include "shipped_materials.h"
#include "test_files.h"
#include "true_layout.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;
using room_reverb::test::writeFile;
using room_reverb::test::trueLayout;
using room_reverb::test::library;
using room_reverb::test::shippedFamilies;
using room_reverb::test::sourcePath;
using room_reverb::test::shippedClassifier;

namespace {

// Brick-like courses (64 x 64): red-brown bricks 24 x 8 pixels in a running bond with
// pale joints, each brick its own tone, times a brightness gain, plus Gaussian noise.
cv::Mat brickPatch(double gain, double noise_sigma) {
  cv::Mat image(64, 64, CV_32FC3);
  cv::RNG rng(7);
  cv::Mat noise(64, 64, CV_32FC3);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, noise_sigma);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const int course = y / 8, shifted = x + (course % 2) * 12;
      const bool joint = y % 8 == 0 || shifted % 24 == 0;
      const double tone = 0.85 + 0.3 * ((course * 7 + shifted / 24 * 13) % 5) / 4.0;
      const cv::Vec3f brick(52.0f, 74.0f, 152.0f);
      const cv::Vec3f mortar(170.0f, 182.0f, 188.0f);
      image.at<cv::Vec3f>(y, x) = (joint ? mortar : brick * static_cast<float>(tone)) * static_cast<float>(gain);
    }
  }
  cv::Mat out;
  cv::Mat(image + noise).convertTo(out, CV_8UC3);  // rounds and saturates
  return out;
}

// An off-white plaster-like patch: smooth mottling only.
cv::Mat plasterPatch() {
  cv::Mat mottle(64, 64, CV_32FC1);
  cv::RNG(3).fill(mottle, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(mottle, mottle, cv::Size(0, 0), 6.0);
  cv::Mat image(64, 64, CV_8UC3);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const double shade = 1.0 + 0.5 * mottle.at<float>(y, x);
      image.at<cv::Vec3b>(y, x) = cv::Vec3b(cv::saturate_cast<uchar>(208 * shade), cv::saturate_cast<uchar>(218 * shade),
                                            cv::saturate_cast<uchar>(222 * shade));
    }
  }
  return image;
}

double distance(const cv::Mat& a, const cv::Mat& b, int from = 1, int to = kMaterialFeatureLength) {
  return cv::norm(a.colRange(from, to), b.colRange(from, to));
}

// Area of the surfaces [m^2] whose assigned family is the true one's, as a fraction of
// all surfaces' area: the box faces, and every object's sides and top.
double areaRight(const RoomModel& truth, const RoomModel& got) {
  auto family = [](const std::string& material) { return textureFamilyFor(library().get(material).name).family; };
  double right = 0.0, all = 0.0;
  const Eigen::Vector3d s = truth.size_m;
  const double face_area[6] = {s.x() * s.y(), s.x() * s.y(), s.y() * s.z(), s.y() * s.z(), s.x() * s.z(), s.x() * s.z()};
  for (std::size_t f = 0; f < 6; ++f) {
    if (f == 1 && !truth.has_ceiling) continue;
    const std::string name = kRoomSurfaceNames[f];
    all += face_area[f];
    if (family(truth.surfaces.at(name).material) == family(got.surfaces.at(name).material)) right += face_area[f];
  }
  for (std::size_t k = 0; k < truth.objects.size(); ++k) {
    const Eigen::Vector3d o = truth.objects[k].size_m;
    const double area = 2.0 * (o.x() + o.y()) * o.z() + o.x() * o.y();
    all += area;
    if (family(truth.objects[k].material) == family(got.objects[k].material)) right += area;
  }
  return right / all;
}

}  // namespace

TEST(MaterialFeatures, FixedLengthAndFinite) {
  const cv::Mat features = materialFeatures(brickPatch(1.0, 2.0));
  ASSERT_EQ(features.rows, 1);
  ASSERT_EQ(features.cols, kMaterialFeatureLength);
  ASSERT_EQ(features.type(), CV_32FC1);
  EXPECT_TRUE(cv::checkRange(features));
  // A black patch and a single-colour one are edge cases of the logs and ratios.
  EXPECT_TRUE(cv::checkRange(materialFeatures(cv::Mat(32, 32, CV_8UC3, cv::Scalar::all(0)))));
  EXPECT_TRUE(cv::checkRange(materialFeatures(cv::Mat(32, 32, CV_8UC3, cv::Scalar(10, 200, 30)))));
}

TEST(MaterialFeatures, ShadingAndNoiseChangeLittleComparedWithAnotherMaterial) {
  const cv::Mat brick = materialFeatures(brickPatch(1.0, 0.0));
  const cv::Mat darker = materialFeatures(brickPatch(0.6, 0.0));
  const cv::Mat noisy = materialFeatures(brickPatch(1.0, 2.0));
  const cv::Mat plaster = materialFeatures(plasterPatch());
  // Only the mean brightness follows the gain.
  EXPECT_NEAR(darker.at<float>(0) / brick.at<float>(0), 0.6, 0.02);
  const double apart = distance(brick, plaster);
  EXPECT_LT(distance(brick, darker), 0.1 * apart);
  EXPECT_LT(distance(brick, noisy), 0.25 * apart);
  // Chromaticity in particular is unchanged by the gain.
  EXPECT_LT(distance(brick, darker, 1, 5), 0.01);
}

TEST(MaterialFeatures, PixelsOutsideTheMaskDoNotMatter) {
  cv::Mat image = brickPatch(1.0, 1.0);
  cv::Mat mask(image.size(), CV_8UC1, cv::Scalar(0));
  cv::circle(mask, cv::Point(32, 32), 20, cv::Scalar(255), cv::FILLED);
  const cv::Mat before = materialFeatures(image, mask);
  cv::Mat other = plasterPatch();
  other.copyTo(image, ~mask);
  EXPECT_EQ(cv::norm(before, materialFeatures(image, mask), cv::NORM_INF), 0.0);
}

TEST(MaterialClassifier, ShippedModelOnHeldOutGeneratedPatches) {
  // Rooms from a seed the shipped model was neither trained nor evaluated on (it used
  // seed 1 and heldOutSeed(1)); smaller widths to keep the test quick.
  MaterialTrainingOptions options;
  options.seed = 20240611;
  options.patches_per_family = 25;
  options.widths = {512, 1024};
  const MaterialSamples samples = generateMaterialSamples(options, library());
  const MaterialAccuracy accuracy = evaluateMaterialClassifier(shippedClassifier(), samples);
  std::cout << "held-out patches: " << samples.features.rows << " from " << samples.rooms << " rooms, accuracy "
            << accuracy.overall() << "\n";
  for (const TextureFamily family : allTextureFamilies()) {
    std::cout << "  " << toString(family) << " " << accuracy.of(family) << "\n";
    EXPECT_GE(accuracy.of(family), 0.6) << toString(family);
  }
  // Measured: 0.94 on these rooms (plaster 0.76 and concrete 0.72 the weakest: pale,
  // weakly textured, told apart mostly by brightness, which shading blurs); 0.98 on the
  // 200-per-family held-out set of the training, which has 2048-wide rooms too.
  EXPECT_GE(accuracy.overall(), 0.9);
}

TEST(MaterialClassifier, SaveLoadRoundTripPredictsTheSame) {
  MaterialTrainingOptions options;
  options.seed = 99;
  options.patches_per_family = 8;
  options.widths = {512};
  const MaterialSamples samples = generateMaterialSamples(options, library());
  MaterialForestParams small;
  small.trees = 10;
  const MaterialClassifier trained = MaterialClassifier::train(samples.features, samples.families, {0.5, 40}, small);
  const std::string path = room_reverb::test::tempPath("small_classifier.yml.gz").string();
  trained.save(path, "a test model");
  const MaterialClassifier loaded = MaterialClassifier::load(path);
  EXPECT_DOUBLE_EQ(loaded.patchGeometry().size_m, 0.5);
  EXPECT_EQ(loaded.patchGeometry().pixels, 40);
  const auto a = trained.predictAll(samples.features), b = loaded.predictAll(samples.features);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].family, b[i].family);
    EXPECT_DOUBLE_EQ(a[i].confidence, b[i].confidence);
    double sum = 0.0;
    for (const double p : a[i].posterior) sum += p;
    EXPECT_NEAR(sum, 1.0, 1e-9);
  }
}

TEST(SurfaceMaterials, GeneratedCapturesWithTheirTrueLayout) {
  for (const std::string name : {"mr", "lounge_furniture"}) {
    CaptureScene scene = loadCaptureScene(sourcePath("data/captures/" + name + ".yaml"));
    scene.options.width = 1024;
    const StereoCapture capture = renderCapture(scene.room, library(), scene.options);
    RoomLayout layout = trueLayout(scene.room);
    const auto decisions =
        assignSurfaceMaterials(layout, capture.top.color, scene.options.baseline_m, shippedClassifier(), shippedFamilies());
    const double right = areaRight(scene.room, layout.model);
    std::cout << name << ": material family right on " << 100.0 * right << " % of the surface area\n";
    EXPECT_GE(right, 0.8) << name;
    EXPECT_EQ(decisions.size(), 6 + scene.room.objects.size());
    for (const auto& decision : decisions) {
      EXPECT_TRUE(library().contains(decision.material)) << decision.name;
      EXPECT_GE(decision.confidence, 0.0);
      EXPECT_LE(decision.confidence, 1.0);
    }
    for (const auto& [face, surface] : layout.model.surfaces) EXPECT_FALSE(surface.material.empty()) << face;
    // The lounge's brick wall repeats along both axes as tiles do (vision/tile_joints.h);
    // only floors and ceilings are asked about their joints.
    if (name == std::string("lounge_furniture")) {
      EXPECT_EQ(textureFamilyFor(layout.model.surfaces.at("wall_x_min").material).family, TextureFamily::kBrick);
    }
    EXPECT_NO_THROW(roomModelToYaml(layout.model));
  }
}

TEST(SurfaceMaterials, AnUnseenFaceGetsTheDefaultWithLowConfidence) {
  // A 4 x 4 pixel image shows nothing well enough: every face is unseen.
  CaptureScene scene = loadCaptureScene(sourcePath("data/captures/mr.yaml"));
  RoomLayout layout = trueLayout(scene.room);
  SurfaceMaterialOptions options;
  const auto decisions = assignSurfaceMaterials(layout, cv::Mat(4, 8, CV_8UC3, cv::Scalar::all(128)), 0.2,
                                                shippedClassifier(), shippedFamilies(), options);
  for (const auto& decision : decisions) {
    EXPECT_FALSE(decision.seen) << decision.name;
    EXPECT_EQ(decision.family, shippedFamilies().unseen_family);
    EXPECT_DOUBLE_EQ(decision.confidence, options.unseen_confidence);
  }
  EXPECT_EQ(layout.model.surfaces.at("floor").material, "plaster_smooth");
}

// A face larger than the patch limit is classified from the patches nearest the camera:
// the courtyard's floor and walls (10 x 19 m, 9 m high) hold 250-550 patch positions each.
TEST(SurfaceMaterials, ALargeFaceTakesItsNearestPatches) {
  CaptureScene scene = loadCaptureScene(sourcePath("data/captures/courtyard.yaml"));
  scene.options.width = 1024;
  const StereoCapture capture = renderCapture(scene.room, library(), scene.options);
  RoomLayout layout = trueLayout(scene.room);
  const Eigen::Isometry3d room_from_camera =
      layout.room_from_rig * Eigen::Translation3d(0.0, 0.0, 0.5 * scene.options.baseline_m);
  material_detail::PatchSampling sampling;
  sampling.geometry = shippedClassifier().patchGeometry();
  const auto all = material_detail::sampleSurfacePatches(capture.top.color, layout.model, room_from_camera, sampling);
  sampling.max_patches_per_rect = 100;
  const auto nearest = material_detail::sampleSurfacePatches(capture.top.color, layout.model, room_from_camera, sampling);
  const auto rects = material_detail::modelSurfaceRects(layout.model);
  const auto range = [&](const material_detail::SurfacePatch& p) {
    // One rectangle per box face (none for the open top).
    const auto& rect = *std::find_if(rects.begin(), rects.end(), [&](const auto& r) { return r.target == p.target; });
    return (rect.center_m + p.s_m * rect.u + p.t_m * rect.v - room_from_camera.translation()).norm();
  };
  int limited_faces = 0;
  for (int face = 0; face < 6; ++face) {
    if (face == 1) continue;  // open to the sky
    std::vector<double> kept, every;
    for (const auto& p : nearest) if (p.target == face) kept.push_back(range(p));
    for (const auto& p : all) if (p.target == face) every.push_back(range(p));
    EXPECT_LE(kept.size(), 100u) << kRoomSurfaceNames[static_cast<std::size_t>(face)];
    if (every.size() <= 100) continue;
    ++limited_faces;
    ASSERT_GE(kept.size(), 50u) << kRoomSurfaceNames[static_cast<std::size_t>(face)];
    // Every patch nearer than the farthest one kept is kept.
    const double farthest = *std::max_element(kept.begin(), kept.end());
    const auto nearer = std::count_if(every.begin(), every.end(), [&](double r) { return r < farthest - 1e-9; });
    EXPECT_GE(static_cast<long>(kept.size()), nearer) << kRoomSurfaceNames[static_cast<std::size_t>(face)];
  }
  EXPECT_GE(limited_faces, 3);
  // With the default limit the faces get the materials they get from every patch.
  RoomLayout limited = layout;
  assignSurfaceMaterials(limited, capture.top.color, scene.options.baseline_m, shippedClassifier(), shippedFamilies());
  SurfaceMaterialOptions unlimited_options;
  unlimited_options.max_patches_per_face = 0;
  assignSurfaceMaterials(layout, capture.top.color, scene.options.baseline_m, shippedClassifier(), shippedFamilies(),
                         unlimited_options);
  for (const auto& [face, surface] : layout.model.surfaces) {
    EXPECT_EQ(limited.model.surfaces.at(face).material, surface.material) << face;
  }
}

TEST(MaterialClassifier, BadInputsAreInputErrors) {
  expectInputError([] { MaterialClassifier::load(sourcePath("config/no_such_classifier.yml.gz")); }, {"no_such_classifier", "no such file"});
  const std::string corrupt = writeFile("corrupt.yml", "%YAML:1.0\nformat: [room_reverb_material_classifier\nmodel: {");
  expectInputError([&] { MaterialClassifier::load(corrupt); }, {"corrupt.yml"});
  const std::string other = writeFile("other.yml", "%YAML:1.0\n---\nformat: something_else\n");
  expectInputError([&] { MaterialClassifier::load(other); }, {"not a material classifier"});
  const std::string wrong_length = writeFile(
      "wrong_length.yml", "%YAML:1.0\n---\nformat: room_reverb_material_classifier\nversion: 1\nfeature_length: 7\n");
  expectInputError([&] { MaterialClassifier::load(wrong_length); }, {"7 features", "retrain"});

  const cv::Mat image = brickPatch(1.0, 0.0);
  expectInputError([] { materialFeatures(cv::Mat()); }, {"empty"});
  expectInputError([] { materialFeatures(cv::Mat(32, 32, CV_8UC1, cv::Scalar(0))); }, {"CV_8UC3"});
  expectInputError([&] { materialFeatures(image, cv::Mat(10, 10, CV_8UC1, cv::Scalar(255))); }, {"mask is 10 x 10"});
  expectInputError([&] { materialFeatures(image, cv::Mat(image.size(), CV_32FC1, cv::Scalar(1))); }, {"CV_8UC1"});
  expectInputError([&] { materialFeatures(image, cv::Mat(image.size(), CV_8UC1, cv::Scalar(0))); }, {"0 pixels"});
  expectInputError([] { shippedClassifier().predict(cv::Mat::zeros(1, 7, CV_32F)); }, {"7"});

  RoomLayout layout = trueLayout(loadCaptureScene(sourcePath("data/captures/mr.yaml")).room);
  const auto assign = [&](const cv::Mat& color, double baseline) {
    assignSurfaceMaterials(layout, color, baseline, shippedClassifier(), shippedFamilies());
  };
  expectInputError([&] { assign(cv::Mat(), 0.2); }, {"empty"});
  expectInputError([&] { assign(cv::Mat(64, 128, CV_8UC1, cv::Scalar(0)), 0.2); }, {"CV_8UC3"});
  expectInputError([&] { assign(cv::Mat(64, 100, CV_8UC3, cv::Scalar::all(0)), 0.2); }, {"twice as wide"});
  expectInputError([&] { assign(cv::Mat(64, 128, CV_8UC3, cv::Scalar::all(0)), -1.0); }, {"baseline"});
  expectInputError([&] { assignSurfaceMaterials(layout, cv::Mat(64, 128, CV_8UC3), 0.2, MaterialClassifier(), shippedFamilies()); },
                   {"not trained"});
  SurfaceMaterialOptions negative_limit;
  negative_limit.max_patches_per_face = -1;
  expectInputError([&] { assignSurfaceMaterials(layout, cv::Mat(64, 128, CV_8UC3, cv::Scalar::all(0)), 0.2, shippedClassifier(),
                                                shippedFamilies(), negative_limit); },
                   {"max_patches_per_face"});
}

TEST(MaterialFamilyTable, ShippedTableCoversEveryFamilyWithItsOwnLook) {
  const MaterialFamilyTable& table = shippedFamilies();
  for (const TextureFamily family : allTextureFamilies()) {
    for (const auto placement : {SurfacePlacement::kFloor, SurfacePlacement::kCeiling, SurfacePlacement::kWall, SurfacePlacement::kObject}) {
      const std::string& material = table.materialFor(family, placement);
      EXPECT_TRUE(library().contains(material)) << material;
      EXPECT_EQ(textureFamilyFor(material).family, family) << material;
    }
  }
  EXPECT_EQ(table.materialFor(TextureFamily::kTiles, SurfacePlacement::kCeiling), "acoustic_ceiling_tiles");
}

TEST(MaterialFamilyTable, BadTablesAreInputErrors) {
  std::string rows;
  for (const TextureFamily family : allTextureFamilies()) {
    if (family != TextureFamily::kPlaster) rows += "  " + toString(family) + ": {material: " + shippedFamilies().families.at(family).material + "}\n";
  }
  const auto parse = [](const std::string& text) { parseMaterialFamilyTable(text, library(), "table.yaml"); };
  EXPECT_NO_THROW(parse("families:\n  plaster: {material: plaster_smooth}\n" + rows));
  expectInputError([&] { parse("families:\n" + rows); }, {"families.plaster", "missing"});
  expectInputError([&] { parse("families:\n  plaster: {material: no_such_material}\n" + rows); }, {"no_such_material", "not a material"});
  expectInputError([&] { parse("families:\n  plaster: {material: brick_bare}\n" + rows); }, {"brick_bare", "looks like brick"});
  expectInputError([&] { parse("families:\n  plaster: {material: plaster_smooth, roof: sheetrock}\n" + rows); }, {"roof", "unknown key"});
  expectInputError([&] { parse("families:\n  plaster: {material: plaster_smooth}\n  marble: {material: marble}\n" + rows); },
                   {"unknown texture family 'marble'"});
  expectInputError([&] { parse("unseen_family: nothing\nfamilies:\n  plaster: {material: plaster_smooth}\n" + rows); },
                   {"unseen_family", "nothing"});
}

TEST(SunRgbdMaterials, EveryClassMapsToALibraryMaterial) {
  const std::set<std::string> expected = {
      "wall", "floor", "cabinet", "bed", "chair", "sofa", "table", "door", "window", "bookshelf", "picture", "counter",
      "blinds", "desk", "shelves", "curtain", "dresser", "pillow", "mirror", "floor_mat", "clothes", "ceiling", "books",
      "fridge", "tv", "paper", "towel", "shower_curtain", "box", "whiteboard", "person", "night_stand", "toilet", "sink",
      "lamp", "bathtub", "bag"};
  const YAML::Node classes = YAML::LoadFile(sourcePath("config/sunrgbd_materials.yaml"))["classes"];
  std::set<std::string> found;
  for (const auto& item : classes) {
    found.insert(item.first.as<std::string>());
    EXPECT_TRUE(library().contains(item.second.as<std::string>())) << item.first.as<std::string>();
  }
  EXPECT_EQ(found, expected);
}
