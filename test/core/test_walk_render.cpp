// A listener walking through a walkable RSAO, offline (binaural/walk_render.h): the pose
// file, its interpolation, a walk towards the source heard louder, and the command line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "reflection_rooms.h"
#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/binaural/walk_render.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/rsao_estimator.h"
#include "room_reverb/rsao/rsao_yaml.h"
#include "spherical_head.h"
#include "synthetic_rir.h"
#include "test_files.h"
#include "tool_run.h"

using namespace room_reverb::core;
using room_reverb::test::expectOneLineError;
using room_reverb::test::runTool;
using room_reverb::test::tempPath;

namespace {

constexpr double kFs = 48000.0;

TEST(PoseFile, ParsesRowsAndInterpolates) {
  const auto poses = parsePoseCsv("t_s, x_m, y_m, z_m, qx, qy, qz, qw\n0,1,2,1.5,0,0,0,1\n\n2,3,2,1.5,0,0,0.7071068,0.7071068\n");
  ASSERT_EQ(poses.size(), 2u);
  const ListenerPose half = poseAt(poses, 1.0);
  EXPECT_NEAR((half.position_m - Eigen::Vector3d(2.0, 2.0, 1.5)).norm(), 0.0, 1e-12);
  // Halfway through a quarter turn about z: 45 degrees.
  EXPECT_NEAR(half.orientation.angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 4.0, Eigen::Vector3d::UnitZ()))),
              0.0, 1e-6);
  EXPECT_EQ(poseAt(poses, -5.0).position_m, poses.front().position_m);
  EXPECT_EQ(poseAt(poses, 50.0).position_m, poses.back().position_m);
}

TEST(PoseFile, BadFilesAreRefusedInOneLineNamingTheLine) {
  const std::string header = "t_s,x_m,y_m,z_m,qx,qy,qz,qw\n";
  const auto refused = [](const std::string& text, const std::string& fragment) {
    try {
      parsePoseCsv(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(fragment), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  };
  refused("", "empty");
  refused("time,x,y,z\n0,1,1,1\n", "the header must be");
  refused(header, "no pose");
  refused(header + "0,1,1,1,0,0,0\n", "line 2: 8 values expected");
  refused(header + "0,1,1,one,0,0,0,1\n", "'one' is not a number");
  refused(header + "0,1,1,nan,0,0,0,1\n", "not finite");
  refused(header + "0,1,1,1,0,0,0,0\n", "zero length");
  refused(header + "1,1,1,1,0,0,0,1\n1,2,1,1,0,0,0,1\n", "line 3: times must increase");
}

// The estimated RSAO of a synthetic room and its model.
struct WalkableRoom {
  room_reverb::test::ReflectionRoom room = room_reverb::test::reflectionRoom(room_reverb::test::ReflectionRoomSet::kDevelopment, 0);
  RoomModel model = room_reverb::test::roomModelOf(room.geometry);
  ListenerTranslation translation{estimateRsao(room.ambix, AmbisonicFormat::kAmbiX), room.geometry.receiver_m,
                                  Eigen::Quaterniond::Identity(), model};
};

double meanSquare(const AudioBuffer& b, double from_s, double to_s) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& channel : b.channels) {
    for (auto i = static_cast<std::size_t>(from_s * kFs); i < static_cast<std::size_t>(to_s * kFs); ++i, ++n) {
      sum += static_cast<double>(channel[i]) * channel[i];
    }
  }
  return sum / static_cast<double>(n);
}

TEST(WalkRender, WalkingTowardsTheSourceIsHeardLouderAndTheOutputIsWhole) {
  const WalkableRoom w;
  const Eigen::Vector3d rig = w.room.geometry.receiver_m, source = w.room.geometry.source_m;
  const double length = (source - rig).norm() - 0.7;
  const Eigen::Vector3d near = rig + length * (source - rig).normalized();
  std::vector<ListenerPose> poses(2);
  poses[0].t_s = 1.0;
  poses[0].position_m = rig;
  poses[1].t_s = 1.0 + length;  // 1 m/s
  poses[1].position_m = near;
  AudioBuffer dry = makeSilentBuffer(1, static_cast<std::size_t>((length + 2.0) * kFs), kFs);
  dry.channels[0] = room_reverb::test::whiteNoise(dry.frameCount(), 3);
  const AudioBuffer out = renderWalk(dry, w.translation, room_reverb::test::sphericalHeadDecoder(3), poses);
  ASSERT_EQ(out.channelCount(), 2u);
  EXPECT_GE(out.durationS(), dry.durationS());
  for (const auto& channel : out.channels)
    for (float v : channel) ASSERT_TRUE(std::isfinite(v));
  // The direct sound alone rises by 20 log10(d / 0.7 m).
  const double gain_db = 10.0 * std::log10(meanSquare(out, length + 1.2, length + 1.9) / meanSquare(out, 0.2, 0.9));
  EXPECT_GT(gain_db, 3.0) << gain_db;
  EXPECT_THROW(renderWalk(dry, w.translation, room_reverb::test::sphericalHeadDecoder(3), {}), InputError);
}

// As a renderer plays a walk: each chunk starts where the last one ended and reaches its own
// targets at its last block; a placed set is where the next chunk starts from.
TEST(WalkRender, ChunkedTargetsRunFromTheLastChunksEndToTheNewest) {
  const auto at = [](double delay_s) {
    TapTarget t;
    t.delay_s = delay_s;
    t.level = 10.0 * delay_s;
    t.direction = Eigen::Vector3d::UnitX();
    return std::vector<TapTarget>{t};
  };
  ChunkedTapTargets targets;
  targets.place(at(0.010));
  targets.beginChunk(at(0.014), 4);
  EXPECT_DOUBLE_EQ(targets.atBlock(0).front().delay_s, 0.011);
  EXPECT_DOUBLE_EQ(targets.atBlock(1).front().delay_s, 0.012);
  EXPECT_DOUBLE_EQ(targets.atBlock(3).front().delay_s, 0.014);
  EXPECT_DOUBLE_EQ(targets.atBlock(3).front().level, 0.14);
  targets.endChunk();
  targets.beginChunk(at(0.022), 2);
  EXPECT_DOUBLE_EQ(targets.atBlock(0).front().delay_s, 0.018);
  EXPECT_DOUBLE_EQ(targets.atBlock(7).front().delay_s, 0.022) << "a block past the chunk holds its end";
  // Placed (a new room): nothing to blend from, the chunk's targets at once.
  targets.place({});
  targets.beginChunk(at(0.030), 4);
  EXPECT_DOUBLE_EQ(targets.atBlock(0).front().delay_s, 0.030);
}

// A chunk's targets blended per block are the targets at the blended position: over a
// chunk's walk (1 cm at 1 m/s) delay and level are linear to well under a sample and
// 0.01 dB, directions to 0.01 degrees.
TEST(WalkRender, TargetsBlendedAcrossAChunkAreTheTargetsOnTheWay) {
  const WalkableRoom w;
  const Eigen::Vector3d from = w.room.geometry.receiver_m + Eigen::Vector3d(0.3, -0.2, 0.05);
  const Eigen::Vector3d step(0.008, 0.006, 0.0);  // 1 cm in a 10.7 ms chunk
  const std::vector<TapTarget> a = tapTargetsAt(w.translation, from), b = tapTargetsAt(w.translation, from + step);
  std::vector<TapTarget> blended;
  int compared = 0;
  for (const double u : {0.25, 0.5, 0.75}) {
    tapTargetsBetween(a, b, u, blended);
    const std::vector<TapTarget> exact = tapTargetsAt(w.translation, from + u * step);
    ASSERT_EQ(blended.size(), exact.size());
    for (std::size_t k = 0; k < exact.size(); ++k) {
      if (a[k].level == 0.0 || b[k].level == 0.0) continue;  // heard at one end only: a fade
      EXPECT_NEAR(blended[k].delay_s, exact[k].delay_s, 0.05 / kFs) << "tap " << k << " at " << u;
      EXPECT_NEAR(20.0 * std::log10(blended[k].level / exact[k].level), 0.0, 0.01) << "tap " << k << " at " << u;
      EXPECT_NEAR(blended[k].direction.norm(), 1.0, 1e-12);
      EXPECT_LT(std::acos(std::min(1.0, blended[k].direction.dot(exact[k].direction))) * 180.0 / M_PI, 0.01)
          << "tap " << k << " at " << u;
      ++compared;
    }
  }
  EXPECT_GE(compared, 3 * 6) << "the direct sound and the first-order reflections at least";
  // The ends are the targets themselves; a blend across a change of room is the new room's.
  tapTargetsBetween(a, b, 1.0, blended);
  for (std::size_t k = 0; k < b.size(); ++k) EXPECT_DOUBLE_EQ(blended[k].delay_s, b[k].delay_s);
  tapTargetsBetween({}, b, 0.5, blended);
  ASSERT_EQ(blended.size(), b.size());
  for (std::size_t k = 0; k < b.size(); ++k) EXPECT_EQ(blended[k].level, b[k].level);
  // Opposite directions have no arc between them: the blend takes the newer one.
  TapTarget east, west;
  east.direction = Eigen::Vector3d::UnitX();
  west.direction = -Eigen::Vector3d::UnitX();
  tapTargetsBetween({east}, {west}, 0.5, blended);
  EXPECT_EQ(blended[0].direction, west.direction);
}

TEST(WalkRender, TheCommandLineWalksAPoseFile) {
  const WalkableRoom w;
  const std::string rsao = tempPath("walk_rsao.yaml").string();
  saveRsaoYaml(rsao, w.translation.measured());
  const std::string room = tempPath("walk_room.yaml").string();
  saveRoomModel(room, w.model);
  const std::string poses = tempPath("walk_poses.csv").string();
  const Eigen::Vector3d rig = w.room.geometry.receiver_m;
  std::ofstream(poses) << "t_s,x_m,y_m,z_m,qx,qy,qz,qw\n0," << rig.x() << "," << rig.y() << "," << rig.z()
                       << ",0,0,0,1\n1," << rig.x() + 0.5 << "," << rig.y() << "," << rig.z() << ",0,0,0.3826834,0.9238795\n";
  const std::string dry = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/dry/speech.wav";
  const std::string out = tempPath("walk.wav").string();
  const auto run = runTool("render --source " + dry + " --rsao " + rsao + " --room " + room + " --poses " + poses +
                           " --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("a listener walking 2 poses"), std::string::npos) << run.out;
  EXPECT_EQ(readAudioFile(out).channelCount(), 2u);

  const std::string base = "render --source " + dry + " --out " + out;
  expectOneLineError(runTool(base + " --bformat-rir " + dry + " --format fuma --poses " + poses), "--poses needs --rsao");
  expectOneLineError(runTool(base + " --rsao " + rsao + " --poses " + poses), "--room ROOM.yaml or --rig X Y Z");
  expectOneLineError(runTool(base + " --rsao " + rsao + " --room " + room), "go with --poses");
  expectOneLineError(runTool(base + " --rsao " + rsao + " --room " + room + " --poses /nonexistent/poses.csv"), "poses.csv");
  const std::string outside = tempPath("walk_outside.csv").string();
  std::ofstream(outside) << "t_s,x_m,y_m,z_m,qx,qy,qz,qw\n0,-3,1,1,0,0,0,1\n";
  expectOneLineError(runTool(base + " --rsao " + rsao + " --room " + room + " --poses " + outside), "the listener");
}

}  // namespace
