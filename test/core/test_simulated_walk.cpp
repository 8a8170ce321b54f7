// The simulated route walked (acoustics/simulated_walk.h, walk_render.h): its early and
// late parts are the simulator's own, a listener standing still hears exactly the static
// render of the simulated response, a listener walking towards the source hears the
// direct sound arrive earlier and louder, and bad positions are refused in one line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/simulated_walk.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/binaural/offline_render.h"
#include "room_reverb/binaural/walk_render.h"
#include "room_reverb/common/error.h"
#include "shoebox.h"
#include "spherical_head.h"
#include "test_files.h"
#include "tool_run.h"

namespace room_reverb::core {
namespace {

const Eigen::Vector3d kSize(6.0, 4.0, 3.0);
const Eigen::Vector3d kSource(1.5, 2.0, 1.5);
const Eigen::Vector3d kReference(4.5, 1.5, 1.5);

SimulationSettings settings() {
  SimulationSettings s;
  s.mode = SimulationMode::kEyring;  // the late part's own method does not matter here
  s.image_source_order = 2;
  s.duration_s = 0.6;
  s.ambisonic_order = 3;
  return s;
}

SimulatedWalk makeWalk() {
  return SimulatedWalk(AcousticScene(test::shoeboxMesh(kSize), test::uniformLibrary(0.2, 0.1)), kSource, kReference,
                       settings());
}

AudioBuffer noise(double seconds, unsigned seed) {
  AudioBuffer b = makeSilentBuffer(1, static_cast<std::size_t>(seconds * kInternalSampleRateHz), kInternalSampleRateHz);
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal(0.0f, 0.1f);
  for (float& v : b.channels[0]) v = normal(rng);
  return b;
}

std::size_t peakIndex(const std::vector<float>& x) {
  std::size_t best = 0;
  for (std::size_t n = 1; n < x.size(); ++n) {
    if (std::abs(x[n]) > std::abs(x[best])) best = n;
  }
  return best;
}

// At the reference position the walk's early part over its late part is `full`, the
// simulator's response, to float rounding.
void expectEarlyPlusLateIs(const SimulatedWalk& walk, const AudioBuffer& full) {
  const AudioBuffer early = walk.earlyAt(kReference);
  ASSERT_EQ(early.channelCount(), 16u);
  ASSERT_EQ(walk.late().frameCount(), full.frameCount());
  ASSERT_LT(early.frameCount(), full.frameCount());
  const AudioBuffer heard = walk.responseAt(kReference);
  ASSERT_EQ(heard.channelCount(), 16u);
  // The same from the early part already computed (what the renderer node checks).
  EXPECT_EQ(walk.responseWith(early).channels, heard.channels);
  ASSERT_EQ(heard.frameCount(), full.frameCount());
  double worst = 0.0, peak = 0.0;
  for (std::size_t c = 0; c < 16; ++c) {
    for (std::size_t n = 0; n < full.frameCount(); ++n) {
      const double sum = walk.late().channels[c][n] + (n < early.frameCount() ? early.channels[c][n] : 0.0f);
      EXPECT_EQ(heard.channels[c][n], static_cast<float>(sum)) << "channel " << c << ", frame " << n;
      if (heard.channels[c][n] != static_cast<float>(sum)) return;
      worst = std::max(worst, std::abs(sum - full.channels[c][n]));
      peak = std::max(peak, static_cast<double>(std::abs(full.channels[c][n])));
    }
  }
  EXPECT_LT(worst, 1e-6 * peak);
}

TEST(SimulatedWalk, EarlyPlusLateIsTheSimulatedResponse) {
  const AcousticScene scene(test::shoeboxMesh(kSize), test::uniformLibrary(0.2, 0.1));
  expectEarlyPlusLateIs(makeWalk(), simulateRoom(scene, kSource, kReference, settings()).impulse_response);
}

// The same in third octaves, with a material whose thirds differ: the early part takes each
// third's gains, the late part each third's energy.
TEST(SimulatedWalk, EarlyPlusLateIsTheSimulatedResponseInThirdOctaves) {
  MaterialLibrary library = test::uniformLibrary(0.2, 0.1);
  AcousticMaterial wall = library.get("test_wall");
  ThirdOctaveValues thirds{};
  thirds[0].fill(0.1);
  thirds[1].fill(0.2);
  thirds[2].fill(0.4);
  wall.absorption_thirds = thirds;
  library.add(wall);
  SimulationSettings in_thirds = settings();
  in_thirds.bands = BandResolution::kThirdOctave;
  const AcousticScene scene(test::shoeboxMesh(kSize), library);
  const SimulationResult full = simulateRoom(scene, kSource, kReference, in_thirds);
  ASSERT_EQ(full.late_thirds.size(), 3u);
  const SimulatedWalk walk(scene, kSource, kReference, in_thirds);
  expectEarlyPlusLateIs(walk, full.impulse_response);
  // Not the octave response: the thirds' absorption reaches the walk.
  const AudioBuffer octave_early = makeWalk().earlyAt(kReference);
  EXPECT_NE(walk.earlyAt(kReference).channels[0], octave_early.channels[0]);
}

TEST(SimulatedWalk, TheEarlyPartFollowsTheListener) {
  const SimulatedWalk walk = makeWalk();
  for (const Eigen::Vector3d& at : {Eigen::Vector3d(4.5, 1.5, 1.5), Eigen::Vector3d(3.0, 2.5, 1.2), Eigen::Vector3d(2.2, 1.0, 1.8)}) {
    const AudioBuffer early = walk.earlyAt(at);
    // The direct sound peaks at distance / c, and nothing comes before it but its filter's
    // faint pre-ringing (coinciding reflections may peak higher later).
    const double c = walk.pathsAt(at).front().distance_m / walk.pathsAt(at).front().delay_s;
    const auto expected = static_cast<long>(std::lround((at - kSource).norm() / c * kInternalSampleRateHz));
    const std::vector<float>& w = early.channels[0];
    const std::vector<float> around(w.begin() + expected - 48, w.begin() + expected + 49);
    EXPECT_NEAR(static_cast<double>(peakIndex(around)), 48.0, 1.0) << "direct sound at " << at.transpose();
    const std::vector<float> before(w.begin(), w.begin() + expected - 24);
    EXPECT_LT(std::abs(before[peakIndex(before)]), 0.05 * std::abs(w[static_cast<std::size_t>(expected)]));
    // Its last path's filter ends in it.
    double last = 0.0;
    for (const SpecularPath& p : walk.pathsAt(at)) last = std::max(last, p.delay_s);
    EXPECT_NEAR(early.durationS(), last + (kPathTapLength / 2 + 1) / kInternalSampleRateHz, 2.0 / kInternalSampleRateHz)
        << "at " << at.transpose();
  }
}

TEST(SimulatedWalk, StandingStillIsTheStaticRender) {
  const SimulatedWalk walk = makeWalk();
  const BinauralDecoder decoder = test::sphericalHeadDecoder(3);
  const AudioBuffer dry = noise(0.5, 3);
  const Eigen::Quaterniond head(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()));
  ListenerPose pose;
  pose.position_m = kReference;
  pose.orientation = head;
  const AudioBuffer walked = renderSimulatedWalk(dry, walk, decoder, {pose});
  const AcousticScene scene(test::shoeboxMesh(kSize), test::uniformLibrary(0.2, 0.1));
  const AudioBuffer full = simulateRoom(scene, kSource, kReference, settings()).impulse_response;
  const AudioBuffer expected = convolveBinaural(dry, binauralRoomResponse(full, decoder, head)).audio;
  ASSERT_EQ(walked.channelCount(), 2u);
  double worst = 0.0, peak = 0.0;
  for (std::size_t c = 0; c < 2; ++c) {
    const std::size_t n_max = std::min(walked.frameCount(), expected.frameCount());
    ASSERT_GT(n_max, dry.frameCount());
    for (std::size_t n = 0; n < n_max; ++n) {
      worst = std::max(worst, static_cast<double>(std::abs(walked.channels[c][n] - expected.channels[c][n])));
      peak = std::max(peak, static_cast<double>(std::abs(expected.channels[c][n])));
    }
  }
  // The stream's partitioned convolution against one long FFT convolution, in single
  // precision: -60 dB.
  EXPECT_LT(worst, 1e-3 * peak);
}

TEST(SimulatedWalk, WalkingTowardsTheSourceIsLouder) {
  const SimulatedWalk walk = makeWalk();
  const BinauralDecoder decoder = test::sphericalHeadDecoder(3);
  const AudioBuffer dry = noise(5.0, 4);
  // From the reference position to 0.8 m from the source at 1 m/s, after a second there.
  const Eigen::Vector3d near = kSource + 0.8 * (kReference - kSource).normalized();
  ListenerPose start, leave, arrive;
  start.position_m = leave.position_m = kReference;
  leave.t_s = 1.0;
  arrive.position_m = near;
  arrive.t_s = 1.0 + (kReference - near).norm();
  const AudioBuffer out = renderSimulatedWalk(dry, walk, decoder, {start, leave, arrive});
  const auto meanSquare = [&](double from_s, double to_s) {
    double sum = 0.0;
    const auto a = static_cast<std::size_t>(from_s * kInternalSampleRateHz), b = static_cast<std::size_t>(to_s * kInternalSampleRateHz);
    for (std::size_t n = a; n < b; ++n) sum += out.channels[0][n] * out.channels[0][n] + out.channels[1][n] * out.channels[1][n];
    return sum / static_cast<double>(b - a);
  };
  const double gain_db = 10.0 * std::log10(meanSquare(arrive.t_s + 0.1, 4.8) / meanSquare(0.3, 1.0));
  // As much louder as the simulated responses' energies say (omni channel: early part at
  // each place, the same late part), within 1 dB.
  const auto energy = [](const std::vector<float>& x) {
    double e = 0.0;
    for (float v : x) e += static_cast<double>(v) * v;
    return e;
  };
  const double late = energy(walk.late().channels[0]);
  const double expected_db = 10.0 * std::log10((energy(walk.earlyAt(near).channels[0]) + late) /
                                               (energy(walk.earlyAt(kReference).channels[0]) + late));
  EXPECT_GT(expected_db, 2.0);
  EXPECT_NEAR(gain_db, expected_db, 1.0);
  // No click on the way: the output's largest step stays within what the static ends have.
  double step_walk = 0.0, step_ends = 0.0;
  for (std::size_t c = 0; c < 2; ++c) {
    for (std::size_t n = 1; n < static_cast<std::size_t>(4.8 * kInternalSampleRateHz); ++n) {
      const double t = static_cast<double>(n) / kInternalSampleRateHz;
      const double step = std::abs(out.channels[c][n] - out.channels[c][n - 1]);
      ((t > 1.0 && t < arrive.t_s) ? step_walk : step_ends) = std::max((t > 1.0 && t < arrive.t_s) ? step_walk : step_ends, step);
    }
  }
  EXPECT_LT(step_walk, 1.5 * step_ends);
}

TEST(SimulatedWalk, BadPositionsAreRefusedInOneLine) {
  const SimulatedWalk walk = makeWalk();
  test::expectInputError([&] { walk.earlyAt(Eigen::Vector3d(7.0, 1.0, 1.0)); }, {"listener"});
  test::expectInputError([&] { walk.earlyAt(Eigen::Vector3d(std::nan(""), 1.0, 1.0)); }, {"not finite"});
  test::expectInputError([&] { walk.earlyAt(kSource + Eigen::Vector3d(0.01, 0.0, 0.0)); }, {"5 cm"});
  test::expectInputError([&] { walk.requireListener(Eigen::Vector3d(1.0, 1.0, -0.5)); }, {"listener"});
  test::expectInputError([&] { walk.responseAt(kSource); }, {"5 cm"});
  test::expectInputError([&] { walk.responseWith(makeSilentBuffer(4, 100, kInternalSampleRateHz)); },
                         {"4 channels", "16"});
  walk.requireListener(kReference);
  ListenerPose outside;
  outside.position_m = Eigen::Vector3d(1.0, -1.0, 1.0);
  test::expectInputError([&] { renderSimulatedWalk(noise(0.1, 1), walk, test::sphericalHeadDecoder(1), {outside}); },
                         {"listener"});
  test::expectInputError(
      [&] { SimulatedWalk(AcousticScene(test::shoeboxMesh(kSize), test::uniformLibrary(0.2, 0.1)), Eigen::Vector3d(9, 1, 1), kReference, settings()); },
      {"source"});
}

TEST(SimulatedWalk, TheCommandLineWalksThroughASimulatedRoom) {
  RoomModel room;
  room.size_m = kSize;
  for (const char* name : kRoomSurfaceNames) {
    room.surfaces[name].material = "plaster_smooth";
  }
  const std::string room_file = test::tempPath("walk_sim_room.yaml").string();
  saveRoomModel(room_file, room);
  const std::string poses = test::tempPath("walk_sim_poses.csv").string();
  std::ofstream(poses) << "t_s,x_m,y_m,z_m,qx,qy,qz,qw\n0,4.5,1.5,1.5,0,0,0,1\n1,3.0,2.0,1.5,0,0,0.3826834,0.9238795\n";
  const std::string dry = std::string(ROOM_REVERB_SOURCE_DIR) + "/data/dry/speech.wav";
  const std::string out = test::tempPath("walk_sim.wav").string();
  const std::string base = "render --source " + dry + " --out " + out;
  const auto run = test::runTool(base + " --room " + room_file + " --source-at 1.5 2 1.5 --poses " + poses +
                                 " --mode eyring --order 2 --duration 0.5");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("the simulated room (eyring) walked through 2 poses"), std::string::npos) << run.out;
  const AudioBuffer written = readAudioFile(out);
  EXPECT_EQ(written.channelCount(), 2u);
  EXPECT_NEAR(written.durationS(), readAudioFile(dry).durationS() + 0.5, 0.01);

  const std::string sim = " --room " + room_file + " --source-at 1.5 2 1.5";
  test::expectOneLineError(test::runTool(base + sim), "--source-at needs --poses");
  test::expectOneLineError(test::runTool(base + " --source-at 1.5 2 1.5 --poses " + poses), "--source-at needs --room");
  test::expectOneLineError(test::runTool(base + sim + " --poses " + poses + " --rsao x.yaml"), "no --bformat-rir");
  test::expectOneLineError(test::runTool(base + sim + " --poses " + poses + " --ambisonic-order 1"), "decoder's");
  test::expectOneLineError(test::runTool(base + " --room " + room_file + " --source-at 9 2 1.5 --poses " + poses +
                                         " --mode eyring"),
                           "source");
  test::expectOneLineError(test::runTool(base + sim + " --poses " + poses + " --mode loud"), "loud");
  test::expectOneLineError(test::runTool(base + " --room " + room_file + " --source-at 1.5 2 --poses " + poses), "source-at");
}

}  // namespace
}  // namespace room_reverb::core
