// Tiles told by their joints over a whole face (vision/tile_joints.h): the face's patches,
// drawn here from known patterns with the differences real patches have (each read from
// its own image level, so sharper or blurrier, brighter or darker), laid side by side.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "room_reverb/vision/tile_joints.h"

using namespace room_reverb::core;
using namespace room_reverb::core::material_detail;

namespace {

constexpr double kPatchM = 0.6;
constexpr int kPixels = 48;

// A face of columns x rows patches, each pixel's grey level from `pattern` (s, t in
// metres), every patch blurred and scaled by its own amount.
std::vector<SurfacePatch> face(int columns, int rows, const std::function<double(double, double)>& pattern,
                               unsigned seed = 1) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> gain(0.8, 1.2), blur(0.0, 1.5);
  std::vector<SurfacePatch> patches;
  const double step = kPatchM / kPixels;
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < columns; ++i) {
      SurfacePatch patch;
      patch.s_m = (i - 0.5 * (columns - 1)) * kPatchM;
      patch.t_m = (j - 0.5 * (rows - 1)) * kPatchM;
      // Drawn with a margin and blurred before the margin is cut away, as a patch is read
      // from a larger image.
      constexpr int kMargin = 8;
      cv::Mat canvas(kPixels + 2 * kMargin, kPixels + 2 * kMargin, CV_8UC1);
      const double g = gain(random);
      for (int r = 0; r < canvas.rows; ++r) {
        for (int c = 0; c < canvas.cols; ++c) {
          const double s = patch.s_m + (c - kMargin + 0.5 - 0.5 * kPixels) * step;
          const double t = patch.t_m + (0.5 * kPixels - (r - kMargin) - 0.5) * step;
          canvas.at<std::uint8_t>(r, c) = cv::saturate_cast<std::uint8_t>(g * pattern(s, t));
        }
      }
      const double sigma = blur(random);
      if (sigma > 0.3) cv::GaussianBlur(canvas, canvas, cv::Size(), sigma);
      const cv::Mat grey = canvas(cv::Rect(kMargin, kMargin, kPixels, kPixels)).clone();
      cv::cvtColor(grey, patch.bgr, cv::COLOR_GRAY2BGR);
      patch.mask = cv::Mat(kPixels, kPixels, CV_8UC1, cv::Scalar(255));
      patch.area_m2 = kPatchM * kPatchM;
      patches.push_back(patch);
    }
  }
  return patches;
}

std::vector<const SurfacePatch*> pointers(const std::vector<SurfacePatch>& patches) {
  std::vector<const SurfacePatch*> out;
  for (const SurfacePatch& p : patches) out.push_back(&p);
  return out;
}

// Square tiles of `size` with 1 cm joints darker than the tiles, and a mottled face.
std::function<double(double, double)> tiles(double size, unsigned seed = 7) {
  auto noise = std::make_shared<cv::Mat>(512, 512, CV_32FC1);
  cv::setRNGSeed(static_cast<int>(seed));
  cv::randn(*noise, 0.0, 12.0);
  // Laid from a corner that is no patch's: where joints meet the patches' edges is chance.
  return [size, noise](double s, double t) {
    s += 0.037, t += 0.052;
    const double us = s / size - std::floor(s / size), ut = t / size - std::floor(t / size);
    const double joint = 0.01 / size;
    const float mottle = noise->at<float>(static_cast<int>(std::fmod(s * 100.0 + 1000.0, 512.0)),
                                          static_cast<int>(std::fmod(t * 100.0 + 1000.0, 512.0)));
    return (us < joint || ut < joint ? 90.0 : 170.0) + mottle;
  };
}

double noiseAt(double s, double t) {
  // A deterministic hash of the point: carpet-like texture with no period.
  const double v = std::sin(s * 1234.567 + t * 7654.321) * 43758.5453;
  return 128.0 + 40.0 * (v - std::floor(v) - 0.5);
}

}  // namespace

TEST(TileJoints, SquareTilesAreAGridAtTheirSize) {
  for (const double size : {0.2, 0.3, 0.45, 0.6}) {
    const auto patches = face(7, 6, tiles(size));
    const JointGrid grid = jointGridOfFace(pointers(patches), kPatchM);
    EXPECT_TRUE(grid.grid) << size << " m: strengths " << grid.strength_s << ", " << grid.strength_t;
    EXPECT_GE(std::min(grid.line_contrast_s, grid.line_contrast_t), 4.0) << size;  // joints 1 cm wide
    EXPECT_NEAR(grid.period_s_m, size, 0.02) << size;
    EXPECT_NEAR(grid.period_t_m, size, 0.02) << size;
  }
}

TEST(TileJoints, PlanksCarpetAndPlainFacesAreNoGrid) {
  // Planks 0.15 m wide along s, their butt joints every 1.2 m staggered from plank to plank.
  const auto planks = [](double s, double t) {
    const int plank = static_cast<int>(std::floor(t / 0.15));
    const double along = s + 0.37 * plank;
    const bool seam = t / 0.15 - std::floor(t / 0.15) < 0.05 || along / 1.2 - std::floor(along / 1.2) < 0.01;
    return (seam ? 80.0 : 150.0) + 10.0 * std::sin(40.0 * s + plank);
  };
  const auto plank_patches = face(7, 6, planks);
  const JointGrid plank_grid = jointGridOfFace(pointers(plank_patches), kPatchM);
  EXPECT_FALSE(plank_grid.grid) << plank_grid.strength_s << ", " << plank_grid.strength_t;
  // Random texture: the patches' own blur and gain differ, and repeat at the patch size;
  // that is no joint.
  const auto carpet = face(7, 6, noiseAt);
  const JointGrid carpet_grid = jointGridOfFace(pointers(carpet), kPatchM);
  EXPECT_FALSE(carpet_grid.grid);
  EXPECT_LT(std::min(carpet_grid.strength_s, carpet_grid.strength_t), 0.3);
  const auto plain = face(7, 6, [](double, double) { return 150.0; });
  EXPECT_FALSE(jointGridOfFace(pointers(plain), kPatchM).grid);
}

TEST(TileJoints, TooLittleOfAFaceSaysNothing) {
  EXPECT_FALSE(jointGridOfFace({}, kPatchM).grid);
  // One patch holds fewer than three periods of anything but the smallest tiles.
  const auto one = face(1, 1, tiles(0.3));
  const JointGrid grid = jointGridOfFace(pointers(one), kPatchM);
  EXPECT_FALSE(grid.grid);
  EXPECT_EQ(grid.strength_s, 0.0);
}

// A brick bond's head joints, staggered by half a brick from course to course, fall every
// half brick in the mean over the courses: it repeats along both axes as tiles do. That is
// why the material step asks only floors and ceilings (test_material_classifier checks
// that a brick wall stays brick).
TEST(TileJoints, ABrickBondRepeatsAlongBothAxes) {
  const auto bond = [](double s, double t) {
    const double course = 0.075, brick = 0.225;
    const int row = static_cast<int>(std::floor(t / course));
    const double along = s + (row % 2 != 0 ? 0.5 * brick : 0.0);
    const bool joint = t / course - std::floor(t / course) < 0.13 || along / brick - std::floor(along / brick) < 0.045;
    return joint ? 200.0 : 110.0;
  };
  const auto patches = face(7, 5, bond);
  const JointGrid grid = jointGridOfFace(pointers(patches), kPatchM);
  EXPECT_GE(grid.strength_s, kGridStrength);
  EXPECT_GE(grid.strength_t, kGridStrength);
  EXPECT_NEAR(grid.period_s_m, 0.1125, 0.015);
}

// Parquet in herringbone: boards 0.1 x 0.2 m at 45 degrees to the face's axes, every other
// one turned a right angle (the domino tiling whose boards along u start where
// (i - j) mod 4 is 0, and those along v where it is 3, in cells of a board's width). Its
// joints repeat along both of the face's axes, but run along neither of them.
double herringbone(double s, double t) {
  constexpr double kWidth = 0.1;
  const double u = (s + t) / std::sqrt(2.0) / kWidth + 0.31, v = (t - s) / std::sqrt(2.0) / kWidth + 0.17;
  const int i = static_cast<int>(std::floor(u)), j = static_cast<int>(std::floor(v));
  const auto residue = [](int a, int b) { return ((a - b) % 4 + 4) % 4; };
  constexpr double kJoint = 0.08;  // of a board's width
  const bool left_joint = u - i < kJoint && residue(i - 1, j) != 0;   // the board to the left is another
  const bool lower_joint = v - j < kJoint && residue(i, j - 1) != 3;  // the board below is another
  // Each board its own shade: the first cell of its board names it.
  const int r = residue(i, j);
  const int board_i = r == 1 ? i - 1 : i, board_j = r == 2 ? j - 1 : j;
  const double shade = 12.0 * std::sin(3.7 * board_i + 5.3 * board_j);
  return (left_joint || lower_joint ? 80.0 : 150.0) + shade + 6.0 * std::sin(60.0 * u);
}

TEST(TileJoints, ParquetInHerringboneIsNoGrid) {
  const auto patches = face(7, 6, herringbone);
  const JointGrid grid = jointGridOfFace(pointers(patches), kPatchM);
  EXPECT_FALSE(grid.grid) << grid.line_contrast_s << ", " << grid.line_contrast_t;
  EXPECT_LT(std::max(grid.line_contrast_s, grid.line_contrast_t), kLineContrast);
}

// Planks 0.15 m wide along s whose grain repeats every 0.6 m along them, as a photograph of
// planks laid over a whole floor does: the pattern repeats along both axes, but along s
// there is no joint line, only the grain coming round again.
TEST(TileJoints, PlanksWhosePhotographRepeatsAreNoGrid) {
  const auto planks = [](double s, double t) {
    const int plank = static_cast<int>(std::floor(t / 0.15));
    const double phase = 2.0 * 3.14159265358979 * s / 0.6;  // the photograph's repeat
    const bool seam = t / 0.15 - std::floor(t / 0.15) < 0.05;
    const double grain = 14.0 * std::sin(phase + 1.3 * plank) + 9.0 * std::sin(3.0 * phase + 0.7 * plank) +
                         6.0 * std::sin(7.0 * phase + 2.1 * plank);
    return (seam ? 80.0 : 150.0) + grain;
  };
  const auto patches = face(7, 6, planks);
  const JointGrid grid = jointGridOfFace(pointers(patches), kPatchM);
  EXPECT_GE(grid.strength_s, kGridStrength) << "the grain repeats";
  EXPECT_GE(grid.line_contrast_t, kLineContrast) << "the seams between planks are lines";
  EXPECT_LT(grid.line_contrast_s, kLineContrast) << "the grain is none";
  EXPECT_FALSE(grid.grid);
}
