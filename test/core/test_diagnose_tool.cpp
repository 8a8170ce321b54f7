// room_reverb diagnose as a user runs it: the files it writes, and a clear one-line error
// (exit 2) for each bad input.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/diagnosis/diagnosis.h"
#include "test_files.h"
#include "test_rooms.h"
#include "tool_run.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

const char* const kRoom = kStudioRoomYaml;

// A B-format RIR of the room itself at one pair (the measurement the tests start from).
std::string measuredFile(const std::string& name, double sample_rate_hz = 48000.0, std::size_t channels = 4) {
  const RoomModel room = parseRoomModel(kRoom);
  const AcousticScene scene = roomModelToScene(room, MaterialLibrary::loadDefault());
  SimulationSettings s;
  s.rays.ray_count = 3000;
  s.duration_s = 0.8;
  s.ambisonic_order = 1;
  AudioBuffer rir = simulateRoom(scene, {1.2, 1.0, 1.4}, {3.6, 2.8, 1.3}, s).impulse_response;
  rir.channels.resize(channels);
  if (sample_rate_hz != 48000.0) {
    // Decimated without a filter: only the rate matters for the error under test.
    const auto step = static_cast<std::size_t>(48000.0 / sample_rate_hz);
    for (auto& c : rir.channels) {
      std::vector<float> d;
      for (std::size_t n = 0; n < c.size(); n += step) d.push_back(c[n]);
      c = d;
    }
    rir.sample_rate_hz = sample_rate_hz;
  }
  const std::string path = tempPath(name).string();
  writeAudioFile(path, rir);
  return path;
}

std::string measurements(const std::string& name, const std::string& file, const std::string& format,
                         const std::string& source = "[1.2, 1.0, 1.4]") {
  std::ostringstream os;
  os << "pairs:\n  - {file: " << file << ", format: " << format << ", source_m: " << source
     << ", receiver_m: [3.6, 2.8, 1.3]}\n";
  return writeFile(name, os.str());
}

TEST(DiagnoseTool, WritesJsonReportPlotsAndTheCorrectedRoom) {
  const std::string room = writeFile("room.yaml", kRoom);
  const std::string meas = measurements("m.yaml", measuredFile("ok.wav"), "ambix");
  const std::string out = tempPath("diag_out").string();
  const ToolRun run = runTool("diagnose --measured " + meas + " --room " + room + " --out " + out +
                              " --causes air_absorption,scattering --rays 2000 --max-causes 1 --noise-seeds 2");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::ifstream in(out + "/diagnosis.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  for (const char* key : {"baseline_error_jnd", "causes", "extended_room"}) EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_GE(j["baseline_error_jnd"].get<double>(), 0.0);
  EXPECT_EQ(j["extended_room"].get<std::string>(), out + "/extended_room.yaml");
  EXPECT_EQ(j["hypotheses"].size(), 2u);
  // The base seed and the two asked for, and the noise is their spread.
  ASSERT_EQ(j["heldout_over_seeds_jnd"].size(), 3u);
  EXPECT_NEAR(j["noise_jnd"].get<double>(), heldoutNoise(j["heldout_over_seeds_jnd"].get<std::vector<double>>()), 1e-3);
  // The measurement is the room itself: nothing may be named.
  EXPECT_TRUE(j["causes"].empty()) << j.dump(2);
  for (const char* file : {"/report.md", "/decay_curves.png", "/error_per_band.png", "/extended_room.yaml"}) {
    EXPECT_TRUE(std::filesystem::exists(out + file)) << file;
  }
  EXPECT_NO_THROW(loadRoomModel(out + "/extended_room.yaml"));
}

TEST(DiagnoseTool, BadInputsGetOneLineErrors) {
  const std::string room = writeFile("room2.yaml", kRoom);
  const std::string out = tempPath("bad_out").string();
  const auto diagnose = [&](const std::string& meas, const std::string& extra = "") {
    return runTool("diagnose --measured " + meas + " --room " + room + " --out " + out + " --rays 500 " + extra);
  };
  const std::string good = measuredFile("good.wav");
  expectOneLineError(diagnose(measurements("outside.yaml", good, "ambix", "[7.0, 1.0, 1.4]")), "outside");
  expectOneLineError(diagnose(measurements("channels.yaml", measuredFile("two.wav", 48000.0, 2), "ambix")),
                     "needs 4 channel(s), the file has 2");
  expectOneLineError(diagnose(measurements("omni4.yaml", good, "omni")), "needs 1 channel(s), the file has 4");
  expectOneLineError(diagnose(measurements("rate.yaml", measuredFile("slow.wav", 8000.0), "ambix")),
                     "too low");
  expectOneLineError(diagnose(measurements("missing.yaml", tempPath("nowhere.wav").string(), "ambix")), "nowhere.wav");
  expectOneLineError(diagnose(writeFile("bands.yaml", "pairs:\n  - {source_m: [1.2, 1.0, 1.4], receiver_m: [3.6, 2.8, 1.3]}\n"
                                                      "parameters:\n  bands_hz: [500, 1000]\n  t20_s: [0.5]\n")),
                     "parameters.t20_s");
  expectOneLineError(diagnose(measurements("cause.yaml", good, "ambix"), "--causes nonsense"), "unknown cause");
  expectOneLineError(diagnose(measurements("seeds.yaml", good, "ambix"), "--noise-seeds 0"), "--noise-seeds must be 1-20");
  const std::string empty_mesh = writeFile("empty.obj", "# no faces\nv 0 0 0\n");
  expectOneLineError(runTool("diagnose --measured " + measurements("mesh.yaml", good, "ambix") + " --mesh " +
                             empty_mesh + " --out " + out),
                     "empty.obj");
  std::vector<float> silence(48000, 0.0f);
  AudioBuffer quiet;
  quiet.channels.assign(4, silence);
  writeAudioFile(tempPath("silent.wav").string(), quiet);
  expectOneLineError(diagnose(measurements("silent.yaml", tempPath("silent.wav").string(), "ambix")), "silent");
  // Workers: a count out of range, a list with no command, a command that is not a worker.
  const std::string meas = measurements("workers.yaml", good, "ambix");
  expectOneLineError(diagnose(meas, "--workers -1"), "--workers must be 0 to 256");
  expectOneLineError(diagnose(meas, "--worker-commands " + writeFile("none.txt", "# nothing here\n\n")),
                     "no worker command");
  expectOneLineError(diagnose(meas, "--worker-commands " + tempPath("no_list.txt").string()), "no_list.txt");
  expectOneLineError(diagnose(meas, "--causes air_absorption --worker-commands " + writeFile("bad.txt", "exit 3\n")),
                     "worker 'exit 3' exited with status 3");
}

TEST(DiagnoseTool, WorkersGiveTheSameDiagnosis) {
  const std::string room = writeFile("room3.yaml", kRoom);
  const std::string meas = measurements("w.yaml", measuredFile("w.wav"), "ambix");
  const std::string args = "diagnose --measured " + meas + " --room " + room +
                           " --causes air_absorption --rays 1000 --max-causes 1 --noise-seeds 2 --out ";
  const ToolRun here = runTool(args + tempPath("w_here").string());
  const ToolRun there = runTool(args + tempPath("w_there").string() + " --workers 2");
  ASSERT_EQ(here.exit_code, 0) << here.err;
  ASSERT_EQ(there.exit_code, 0) << there.err;
  EXPECT_NE(there.out.find("simulated on 2 worker processes"), std::string::npos) << there.out;
  const auto figures = [](const std::string& dir) {
    nlohmann::json j = nlohmann::json::parse(std::ifstream(dir + "/diagnosis.json"));
    j.erase("wall_time_s");
    j.erase("extended_room");
    return j;
  };
  EXPECT_EQ(figures(tempPath("w_here").string()), figures(tempPath("w_there").string()));
}

}  // namespace
}  // namespace room_reverb::test
