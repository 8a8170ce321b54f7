// room_reverb make-capture, run as a user would: the files it writes and what is in them,
// and every bad input an exit 2 with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>

#include "room_reverb/synthetic_capture/capture_scene.h"
#include "test_files.h"
#include "tool_run.h"

using namespace room_reverb::core;
using room_reverb::test::expectOneLineError;
using room_reverb::test::runTool;
using room_reverb::test::tempPath;
using room_reverb::test::writeFile;

namespace {

std::string scenePath(const std::string& name) { return std::string(ROOM_REVERB_SOURCE_DIR) + "/data/captures/" + name; }

std::string fileBytes(const std::filesystem::path& path) {
  std::stringstream bytes;
  bytes << std::ifstream(path, std::ios::binary).rdbuf();
  return bytes.str();
}

// The MR scene with one line replaced.
std::string mrWith(const std::string& from, const std::string& to) {
  std::string text = fileBytes(scenePath("mr.yaml"));
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

}  // namespace

TEST(MakeCaptureTool, WritesImagesTruthAndTheSceneAsRendered) {
  const std::string out = tempPath("capture_mr").string();
  const auto run = runTool("make-capture --scene " + scenePath("mr.yaml") + " --out " + out + " --width 128 --seed 3 --fisheye");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("wrote"), std::string::npos);
  for (const std::string cam : {"top", "bottom"}) {
    const cv::Mat color = cv::imread(out + "/" + cam + ".png", cv::IMREAD_UNCHANGED);
    EXPECT_EQ(color.type(), CV_8UC3);
    EXPECT_EQ(color.size(), cv::Size(128, 64));
    const cv::Mat range = cv::imread(out + "/" + cam + "_range.tiff", cv::IMREAD_UNCHANGED);
    ASSERT_EQ(range.type(), CV_32FC1) << cam;
    double low = 0, high = 0;
    cv::minMaxLoc(range, &low, &high);
    EXPECT_GT(low, 0.0);
    EXPECT_LT(high, std::sqrt(5.61 * 5.61 + 4.28 * 4.28 + 2.33 * 2.33));  // a closed room: no sky
    EXPECT_EQ(cv::imread(out + "/" + cam + "_material.png", cv::IMREAD_UNCHANGED).type(), CV_16UC1);
    EXPECT_EQ(cv::imread(out + "/" + cam + "_object.png", cv::IMREAD_UNCHANGED).type(), CV_16UC1);
    const cv::Mat fisheye = cv::imread(out + "/" + cam + "_fisheye.png", cv::IMREAD_UNCHANGED);
    EXPECT_EQ(fisheye.size(), cv::Size(128, 64));
  }
  // scene.yaml is a capture scene again (it renders the same capture) and names the ids.
  const CaptureScene scene = loadCaptureScene(out + "/scene.yaml");
  EXPECT_EQ(scene.options.width, 128);
  EXPECT_EQ(scene.options.seed, 3u);
  EXPECT_TRUE(scene.options.fisheye);
  const std::string text = fileBytes(out + "/scene.yaml");
  EXPECT_NE(text.find("material_ids: [carpet_on_concrete, acoustic_ceiling_tiles, plaster_smooth"), std::string::npos) << text;
  EXPECT_NE(text.find("object_ids: [floor, ceiling, wall_x_min, wall_x_max, wall_y_min, wall_y_max, loudspeaker"),
            std::string::npos);
  EXPECT_NE(text.find("top_camera_m: [0.33, 2.12, 1.1]"), std::string::npos);

  // The same command again gives the same bytes.
  const std::string again = tempPath("capture_mr_again").string();
  ASSERT_EQ(runTool("make-capture --scene " + out + "/scene.yaml --out " + again).exit_code, 0);
  EXPECT_EQ(fileBytes(out + "/top.png"), fileBytes(again + "/top.png"));
  EXPECT_EQ(fileBytes(out + "/bottom_fisheye.png"), fileBytes(again + "/bottom_fisheye.png"));
}

TEST(MakeCaptureTool, OptionsOverrideTheScene) {
  const std::string out = tempPath("capture_options").string();
  const auto run = runTool("make-capture --scene " + scenePath("plain_office.yaml") + " --out " + out +
                           " --width 64 --baseline 0.3 --noise 2 --no-shading --supersampling 1");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const CaptureScene scene = loadCaptureScene(out + "/scene.yaml");
  EXPECT_EQ(scene.options.baseline_m, 0.3);
  EXPECT_EQ(scene.options.noise_sigma, 2.0);
  EXPECT_FALSE(scene.options.shading);
  EXPECT_EQ(scene.options.low_texture_materials, std::vector<std::string>{"sheetrock"});
  EXPECT_FALSE(std::filesystem::exists(out + "/top_fisheye.png"));
}

TEST(MakeCaptureTool, BadInputExitsWithOneLine) {
  const std::string out = " --out " + tempPath("capture_bad").string();
  expectOneLineError(runTool("make-capture --scene /nonexistent/scene.yaml" + out), "no such file");
  expectOneLineError(runTool("make-capture --scene " + scenePath("mr.yaml") + out + " --width 127"), "even");
  expectOneLineError(runTool("make-capture --scene " + scenePath("mr.yaml") + out + " --width 32"), "at least 64");
  expectOneLineError(runTool("make-capture --scene " + scenePath("mr.yaml") + out + " --baseline 0"), "baseline");
  expectOneLineError(runTool("make-capture --scene " + scenePath("mr.yaml") + out + " --baseline -0.2"), "baseline");
  expectOneLineError(runTool("make-capture --scene " + scenePath("mr.yaml")), "--out");
  expectOneLineError(runTool("make-capture --scene " + scenePath("mr.yaml") + out + " --width wide"), "integer");
  expectOneLineError(runTool("make-capture --scene " + scenePath("mr.yaml") + out + " --seed -1"), "--seed");
  expectOneLineError(runTool("make-capture --scene " + scenePath("mr.yaml") + out + " --fisheye --calibration /nonexistent/c.yaml"),
                     "no such file");

  const std::string inside = writeFile("inside_table.yaml", mrWith("position_m: [0.33, 2.12, 1.00]", "position_m: [4.40, 2.14, 0.50]"));
  expectOneLineError(runTool("make-capture --scene " + inside + out), "inside objects[2] (table)");
  const std::string outside = writeFile("outside.yaml", mrWith("position_m: [0.33, 2.12, 1.00]", "position_m: [0.33, 5.0, 1.00]"));
  expectOneLineError(runTool("make-capture --scene " + outside + out), "outside the room box");
  const std::string unknown = writeFile("unknown.yaml", mrWith("material: carpet_on_concrete", "material: carpet_on_conrete"));
  expectOneLineError(runTool("make-capture --scene " + unknown + out), "unknown material 'carpet_on_conrete'");
}
