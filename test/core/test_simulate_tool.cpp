// room_reverb simulate and compare on bad input: exit 2 with one line on stderr that says
// what is wrong, never a crash.
#include <gtest/gtest.h>

#include "room_reverb/audio/audio_file.h"
#include "test_files.h"
#include "tool_run.h"

namespace {

using room_reverb::test::runTool;
using room_reverb::test::ToolRun;
using room_reverb::test::writeFile;

const char* kCube = R"(o box
v 0 0 0
v 4 0 0
v 4 3 0
v 0 3 0
v 0 0 2.5
v 4 0 2.5
v 4 3 2.5
v 0 3 2.5
usemtl MATERIAL
f 1 2 3
f 1 3 4
f 5 7 6
f 5 8 7
f 1 6 2
f 1 5 6
f 2 7 3
f 2 6 7
f 3 8 4
f 3 7 8
f 4 5 1
f 4 8 5
)";

std::string cube(const std::string& name, const std::string& material) {
  std::string text = kCube;
  text.replace(text.find("MATERIAL"), 8, material);
  return writeFile(name, text);
}

void expectExit2(const std::string& args, const std::string& fragment) {
  const ToolRun run = runTool(args);
  EXPECT_EQ(run.exit_code, 2) << args << "\n" << run.err;
  EXPECT_NE(run.err.find(fragment), std::string::npos) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
}

const std::string kInside = " --source 1 1 1.2 --listener 3 2 1.5 --rays 200 --duration 0.3";

TEST(SimulateTool, WritesAnAmbisonicResponse) {
  const std::string out = room_reverb::test::tempPath("sim_ok.wav").string();
  const ToolRun run = runTool("simulate --mesh " + cube("ok.obj", "concrete") + kInside + " --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto ir = room_reverb::core::readAudioFile(out);
  EXPECT_EQ(ir.channelCount(), 4u);
  EXPECT_EQ(ir.frameCount(), 14400u);
}

TEST(SimulateTool, BadInputExitsTwoWithAReason) {
  const std::string out = " --out " + room_reverb::test::tempPath("sim_bad.wav").string();
  expectExit2("simulate --mesh " + writeFile("garbage.obj", "v 1 2\nf 1 2 3 4 5\n") + kInside + out, "garbage.obj");
  expectExit2("simulate --mesh " + writeFile("empty.obj", "# nothing\n") + kInside + out, "empty.obj");
  std::string nan_mesh = kCube;
  nan_mesh.replace(nan_mesh.find("v 4 0 0"), 7, "v nan 0 0");
  nan_mesh.replace(nan_mesh.find("MATERIAL"), 8, "concrete");
  expectExit2("simulate --mesh " + writeFile("nan.obj", nan_mesh) + kInside + out, "finite");
  expectExit2("simulate --mesh " + cube("unknown.obj", "marshmallow") + kInside + out, "marshmallow");
  const std::string good = cube("good.obj", "concrete");
  expectExit2("simulate --mesh " + good + " --source 9 1 1 --listener 3 2 1.5 --rays 200" + out, "outside");
  expectExit2("simulate --mesh " + good + " --source 1 1 0.0 --listener 3 2 1.5 --rays 200" + out, "source");
  expectExit2("simulate --mesh " + good + kInside + " --rays 0" + out, "--rays");
  expectExit2("simulate --mesh " + good + kInside + " --scattering 1.5" + out, "scattering");
  expectExit2("simulate --mesh /nonexistent/room.obj" + kInside + out, "/nonexistent/room.obj");
  const std::string bad_library = writeFile("bad_materials.yaml", R"(bands_hz: [63, 125, 250, 500, 1000, 2000, 4000, 8000, 16000]
materials:
  hot_panel:
    description: "a panel that absorbs more than arrives"
    absorption: [0.1, 0.1, 0.1, 0.1, 1.4, 0.1, 0.1, 0.1, 0.1]
    scattering: [0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1]
    source: "test"
)");
  expectExit2("simulate --mesh " + cube("hot.obj", "hot_panel") + kInside + " --materials " + bad_library + out, "hot_panel");
  expectExit2("simulate --mesh " + good + kInside + " --mode quantum" + out, "quantum");
  expectExit2("simulate --mesh " + good + kInside + " --mode fast --fast-track-radius 0" + out, "--fast-track-radius");
  expectExit2("simulate --mesh " + good + kInside + " --mode fast --fast-tolerance 1.5" + out, "--fast-tolerance");
  expectExit2("simulate --mesh " + good + kInside + " --mode fast --fast-launch-mixture 1" + out, "--fast-launch-mixture");
  expectExit2("simulate --mesh " + good + kInside + " --mode fast --fast-launch-mixture -0.2" + out, "--fast-launch-mixture");
  expectExit2("simulate --mesh " + good + kInside + " --order 60" + out, "candidate paths");
  expectExit2("simulate --mesh " + good + " --source 1 1 --listener 3 2 1.5" + out, "--source");
  expectExit2("simulate --mesh " + good + kInside + " --low-band fdtd" + out, "fdtd");
  expectExit2("simulate --mesh " + good + kInside + " --bands fifth" + out, "fifth");
  expectExit2("simulate --mesh " + good + kInside + " --crossover 300" + out, "--low-band wave");
  expectExit2("simulate --mesh " + good + kInside + " --low-band wave --crossover 20" + out, "crossover");
  // 3 cm from the floor: inside the wave solver's first cell (6.9 cm at 500 Hz).
  expectExit2("simulate --mesh " + good + " --source 1 1 0.03 --listener 3 2 1.5 --rays 200 --duration 0.3 --low-band wave" + out,
              "grid cell");
}

TEST(SimulateTool, TheWaveLowBandWritesAResponse) {
  const std::string out = room_reverb::test::tempPath("sim_wave.wav").string();
  const ToolRun run = runTool("simulate --mesh " + cube("wave.obj", "concrete") + kInside + " --low-band wave --crossover 200 --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto ir = room_reverb::core::readAudioFile(out);
  EXPECT_EQ(ir.channelCount(), 4u);
  EXPECT_EQ(ir.frameCount(), 14400u);
}

TEST(SimulateTool, ThirdOctavesUseTheMaterialsThirds) {
  const std::string out = room_reverb::test::tempPath("sim_thirds.wav").string();
  const ToolRun run = runTool("simulate --mesh " + cube("thirds.obj", "mat_CR2_plaster") + kInside +
                              " --bands third --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("in third octaves (the materials' thirds"), std::string::npos) << run.out;
  EXPECT_EQ(room_reverb::core::readAudioFile(out).frameCount(), 14400u);
  const ToolRun plain = runTool("simulate --mesh " + cube("plain.obj", "concrete") + kInside +
                                " --bands third --out " + out);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_NE(plain.out.find("no material has thirds"), std::string::npos) << plain.out;
}

// Units flush against the walls, the floor, the ceiling and each other, as the visual
// route fits a kitchen: the air between them is simulated, a listener in a unit is refused
// with the unit's number and label.
const char* kFlushKitchen = R"(frame: room
room_box: {size_m: [6.0, 4.0, 2.7], has_ceiling: true}
surfaces:
  floor: {material: tiles_ceramic}
  ceiling: {material: plaster_smooth}
  wall_x_min: {material: plaster_smooth}
  wall_x_max: {material: plaster_smooth}
  wall_y_min: {material: plaster_smooth}
  wall_y_max: {material: plaster_smooth}
objects:
  - {label: counter_run, material: wood_panel, center_m: [3.0, 0.3, 0.45], size_m: [6.0, 0.6, 0.9]}
  - {label: wall_cabinets, material: wood_panel, center_m: [3.0, 0.175, 2.35], size_m: [6.0, 0.35, 0.7]}
  - {label: fridge, material: metal, center_m: [0.35, 3.65, 0.95], size_m: [0.7, 0.7, 1.9]}
  - {label: tall_cupboard, material: wood_panel, center_m: [1.0, 3.7, 1.35], size_m: [0.6, 0.6, 2.7]}
  - {label: cabinet, material: wood_panel, center_m: [3.0, 2.2, 0.9], size_m: [6.0, 1.2, 1.8]}
)";

TEST(SimulateTool, ARoomModelWithFlushUnitsSimulatesAndNamesAUnitHoldingTheListener) {
  const std::string room = writeFile("flush_kitchen.yaml", kFlushKitchen);
  const std::string out = room_reverb::test::tempPath("sim_kitchen.wav").string();
  const std::string rays = " --rays 200 --duration 0.3 --out " + out;
  const ToolRun run = runTool("simulate --room " + room + " --source 2.25 3.25 1.25 --listener 4.25 0.75 1.75" + rays);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(room_reverb::core::readAudioFile(out).frameCount(), 14400u);
  expectExit2("simulate --room " + room + " --source 2.25 3.25 1.25 --listener 3 2.2 1.2" + rays,
              "listener (3, 2.2, 1.2) m is inside object 4 (cabinet)");
}

TEST(CompareTool, BadInputExitsTwoWithAReason) {
  expectExit2("compare --measurements /nonexistent/measurements.yaml", "/nonexistent/measurements.yaml");
  const std::string no_room = writeFile("no_room.yaml", "pairs:\n  - {source_m: [1, 1, 1], receiver_m: [2, 2, 1]}\n"
                                                        "parameters: {bands_hz: [1000], t20_s: [1.0]}\n");
  expectExit2("compare --measurements " + no_room, "no room");
  expectExit2("compare", "--measurements");
}

}  // namespace
