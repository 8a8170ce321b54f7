#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <random>

#include "room_reverb/common/error.h"
#include "room_reverb/rsao/rsao_visr_json.h"
#include "room_reverb/rsao/rsao_yaml.h"

using namespace room_reverb::core;

namespace {

// An Rsao with awkward numbers everywhere: angles that are not round in degrees, values
// that need all 17 digits, reasons with quotes, colons and a newline.
Rsao awkwardRsao(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Rsao r;
  r.sample_rate_hz = 48000.0;
  r.duration_s = 1.0 + unit(rng);
  for (int k = 0; k < 5; ++k) {
    EarlyReflection e;
    e.time_of_arrival_s = 0.003 + 0.01 * k + 1e-3 * unit(rng);
    e.level = (k == 0 ? 0.5 : 0.2) * unit(rng) + 0.01;
    e.azimuth_rad = -M_PI + 2.0 * M_PI * unit(rng);
    e.elevation_rad = -0.5 * M_PI + M_PI * unit(rng);
    e.distance_m = 343.0 * e.time_of_arrival_s;
    e.lpc = {1.0, -1.0 * unit(rng), 0.3 * unit(rng)};
    e.lpc_gain = unit(rng);
    e.sos = {BiquadSection{unit(rng), 0.1 * unit(rng), 0.0, -0.5 * unit(rng), 0.25 * unit(rng)}};
    if (k != 2) e.confidence = unit(rng);  // reflection 2 without: as read from an older file
    r.reflections.push_back(e);
  }
  r.reflections[0].azimuth_rad = 0.1;  // 0.1 rad = 5.729577951308232 deg: no short decimal either way
  r.late.onset_s = r.reflections[1].time_of_arrival_s;
  r.late.mixing_time_s = 0.0731 + 1e-4 * unit(rng);
  r.late.attack_time_s = r.late.mixing_time_s - r.late.onset_s;
  r.late.course_end_s = r.late.mixing_time_s + 0.05;
  const auto bands = standardBands(BandResolution::kOctave);
  for (std::size_t b = 0; b < bands.size(); ++b) {
    LateReverbBand band;
    band.center_hz = bands[b].center_hz;
    band.decay_constant_per_s = 3.0 + 10.0 * unit(rng);
    band.t60_s = 3.0 * std::log(10.0) / band.decay_constant_per_s;
    band.level = 0.01 + 0.05 * unit(rng);
    band.onset_level = b % 2 == 0 ? 0.0 : band.level * (1.0 + 3.0 * unit(rng));  // both kinds of early course
    if (b % 3 == 1) {  // bent decays beside single ones
      band.first_decay_constant_per_s = band.decay_constant_per_s * (1.5 + unit(rng));
      band.second_decay_constant_per_s = band.decay_constant_per_s * (0.3 + 0.5 * unit(rng));
      band.second_share = 0.01 + 0.3 * unit(rng);
    }
    band.reliable = b != 8;
    band.reason = b == 8 ? "noise-dominated: \"16 kHz\" band;\nsubstituted" : "";
    r.late.bands.push_back(band);
  }
  r.warnings = {"direct sound: clipped? no", "tab\there"};
  return r;
}

void expectSameRsao(const Rsao& a, const Rsao& b) {
  EXPECT_EQ(a.sample_rate_hz, b.sample_rate_hz);
  EXPECT_EQ(a.duration_s, b.duration_s);
  ASSERT_EQ(a.reflections.size(), b.reflections.size());
  for (std::size_t k = 0; k < a.reflections.size(); ++k) {
    const EarlyReflection &x = a.reflections[k], &y = b.reflections[k];
    EXPECT_EQ(x.time_of_arrival_s, y.time_of_arrival_s);
    EXPECT_EQ(x.level, y.level);
    // Degrees in the file: back to radians within an ulp or two.
    EXPECT_NEAR(x.azimuth_rad, y.azimuth_rad, 1e-15);
    EXPECT_NEAR(x.elevation_rad, y.elevation_rad, 1e-15);
    EXPECT_EQ(x.distance_m, y.distance_m);
    EXPECT_EQ(x.confidence, y.confidence);
    EXPECT_EQ(x.lpc, y.lpc);
    EXPECT_EQ(x.lpc_gain, y.lpc_gain);
    ASSERT_EQ(x.sos.size(), y.sos.size());
    for (std::size_t i = 0; i < x.sos.size(); ++i) {
      EXPECT_EQ(x.sos[i].b0, y.sos[i].b0);
      EXPECT_EQ(x.sos[i].b1, y.sos[i].b1);
      EXPECT_EQ(x.sos[i].b2, y.sos[i].b2);
      EXPECT_EQ(x.sos[i].a1, y.sos[i].a1);
      EXPECT_EQ(x.sos[i].a2, y.sos[i].a2);
    }
  }
  EXPECT_EQ(a.late.mixing_time_s, b.late.mixing_time_s);
  EXPECT_EQ(a.late.onset_s, b.late.onset_s);
  EXPECT_EQ(a.late.attack_time_s, b.late.attack_time_s);
  EXPECT_EQ(a.late.course_end_s, b.late.course_end_s);
  ASSERT_EQ(a.late.bands.size(), b.late.bands.size());
  for (std::size_t i = 0; i < a.late.bands.size(); ++i) {
    EXPECT_EQ(a.late.bands[i].center_hz, b.late.bands[i].center_hz);
    EXPECT_EQ(a.late.bands[i].decay_constant_per_s, b.late.bands[i].decay_constant_per_s);
    EXPECT_EQ(a.late.bands[i].t60_s, b.late.bands[i].t60_s);
    EXPECT_EQ(a.late.bands[i].level, b.late.bands[i].level);
    EXPECT_EQ(a.late.bands[i].onset_level, b.late.bands[i].onset_level);
    EXPECT_EQ(a.late.bands[i].first_decay_constant_per_s, b.late.bands[i].first_decay_constant_per_s);
    EXPECT_EQ(a.late.bands[i].second_decay_constant_per_s, b.late.bands[i].second_decay_constant_per_s);
    EXPECT_EQ(a.late.bands[i].second_share, b.late.bands[i].second_share);
    EXPECT_EQ(a.late.bands[i].reliable, b.late.bands[i].reliable);
    EXPECT_EQ(a.late.bands[i].reason, b.late.bands[i].reason);
  }
  EXPECT_EQ(a.warnings, b.warnings);
}

// Expects `action` to throw InputError whose message contains `needle`.
template <typename F>
void expectInputError(F action, const std::string& needle) {
  try {
    action();
    ADD_FAILURE() << "no InputError (expected one mentioning '" << needle << "')";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// YAML
// ---------------------------------------------------------------------------------------

TEST(RsaoYaml, RoundTripIsExact) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    const Rsao original = awkwardRsao(seed);
    const std::string text = rsaoToYaml(original);
    const Rsao read = parseRsaoYaml(text);
    expectSameRsao(original, read);
    EXPECT_EQ(rsaoToYaml(read), text);
  }
  EXPECT_NE(rsaoToYaml(awkwardRsao(1)).find("azimuth_deg: 5.729577951308232\n"), std::string::npos);
}

TEST(RsaoYaml, EachReflectionCarriesItsImageSourceAndConfidence) {
  Rsao r = awkwardRsao(9);
  r.reflections[1].distance_m = 5.0;
  r.reflections[1].azimuth_rad = M_PI / 2;  // +y, level
  r.reflections[1].elevation_rad = 0.0;
  r.reflections[1].confidence = 0.75;
  const std::array<double, 3> image = imageSourcePosition(r.reflections[1]);
  EXPECT_NEAR(image[0], 0.0, 1e-12);
  EXPECT_NEAR(image[1], 5.0, 1e-12);
  EXPECT_NEAR(image[2], 0.0, 1e-12);
  r.reflections[1].azimuth_rad = 0.0;
  r.reflections[1].elevation_rad = M_PI / 6;  // 30 degrees up, ahead
  const std::string text = rsaoToYaml(r);
  EXPECT_NE(text.find("    image_source_m: [4.330127018922194, 0, 2.4999999999999996]\n    confidence: 0.75\n"),
            std::string::npos)
      << text;
  // An RSAO without confidences (another tool's, or an older file) writes none and reads back none.
  const auto without = text.find("    confidence: 0.75\n");
  const Rsao read = parseRsaoYaml(text.substr(0, without) + text.substr(without + 21));
  EXPECT_FALSE(read.reflections[1].confidence.has_value());
  EXPECT_FALSE(read.reflections[2].confidence.has_value());
  expectInputError([&] { parseRsaoYaml(replaced(text, "confidence: 0.75", "confidence: 1.5")); },
                   "reflections[1].confidence: must lie in 0..1");
  expectInputError([&] { parseRsaoYaml(replaced(text, "confidence: 0.75", "confidence: high")); },
                   "reflections[1].confidence");
}

TEST(RsaoYaml, DegreesInTheFileRoundTripForAnyAngle) {
  // Write -> read -> write must give the same degrees for every angle, not just most.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  Rsao r = awkwardRsao(5);
  for (int trial = 0; trial < 500; ++trial) {
    for (EarlyReflection& e : r.reflections) {
      e.azimuth_rad = angle(rng);
      e.elevation_rad = 0.5 * angle(rng);
    }
    const std::string text = rsaoToYaml(r);
    ASSERT_EQ(rsaoToYaml(parseRsaoYaml(text)), text) << trial;
  }
}

TEST(RsaoYaml, SavesAndLoadsAFile) {
  const Rsao original = awkwardRsao(6);
  const std::string path = ::testing::TempDir() + "rsao_roundtrip.yaml";
  saveRsaoYaml(path, original);
  expectSameRsao(original, loadRsaoYaml(path));
  std::remove(path.c_str());
  expectInputError([&] { loadRsaoYaml(path); }, path);
}

TEST(RsaoYaml, BadInputNamesTheKey) {
  const std::string good = rsaoToYaml(awkwardRsao(7));
  // A missing required key.
  const auto level_at = good.find("    level: ");
  const std::string no_level = good.substr(0, level_at) + good.substr(good.find('\n', level_at) + 1);
  expectInputError([&] { parseRsaoYaml(no_level); }, "reflections[0].level: missing");
  expectInputError([&] { parseRsaoYaml(replaced(good, "late:\n", "early:\n")); }, "late: missing");
  // Not a number.
  expectInputError([&] { parseRsaoYaml(replaced(good, "duration_s: ", "duration_s: long")); }, "duration_s: 'long");
  expectInputError([&] { parseRsaoYaml(replaced(good, "mixing_time_s: ", "mixing_time_s: x")); }, "late.mixing_time_s");
  // Wrong list length: eight bands.
  const auto last_band = good.rfind("    - {center_hz");
  const std::string eight = good.substr(0, last_band) + good.substr(good.find('\n', last_band) + 1);
  expectInputError([&] { parseRsaoYaml(eight); }, "late.bands: must be a list of the nine octave bands");
  // A section without a2.
  const auto a2 = good.find(", a2: ");
  const std::string no_a2 = good.substr(0, a2) + good.substr(good.find('}', a2));
  expectInputError([&] { parseRsaoYaml(no_a2); }, "reflections[0].sos[0].a2: missing");
  expectInputError([&] { parseRsaoYaml(replaced(good, "lpc: [1, ", "lpc: [2, ")); }, "reflections[0].lpc");
  expectInputError([&] { parseRsaoYaml(replaced(good, "t60_s: ", "t60_s: 9")); }, "disagree");
  // A bent decay with a share outside (0, 1), or without its decay constants.
  expectInputError([&] { parseRsaoYaml(replaced(good, "second_share: ", "second_share: 1")); },
                   "late.bands[1]: has two slopes: second_share must lie in (0, 1)");
  expectInputError([&] { parseRsaoYaml(replaced(good, "first_decay_constant_per_s: ", "first_decay: ")); },
                   "late.bands[1].first_decay_constant_per_s: missing");
  expectInputError([&] { parseRsaoYaml(replaced(good, "format: room_reverb_rsao", "format: other")); }, "format");
  expectInputError([&] { parseRsaoYaml("reflections: [\n"); }, "not valid YAML");
  expectInputError([&] { parseRsaoYaml("- 1\n- 2\n"); }, "not an RSAO file");
}

TEST(RsaoYaml, RefusesToWriteWhatWouldNotReadBack) {
  Rsao r = awkwardRsao(8);
  r.late.bands[2].level = std::nan("");
  expectInputError([&] { rsaoToYaml(r); }, "late.bands[2]");
}

// ---------------------------------------------------------------------------------------
// VISR JSON
// ---------------------------------------------------------------------------------------

TEST(RsaoVisrJson, ExportImportExportGivesIdenticalText) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    const Rsao original = awkwardRsao(seed);
    VisrObjectFields fields;
    fields.id = 3;
    fields.channel = 5;
    const std::string text = rsaoToVisrJson(original, fields);
    const VisrImport imported = visrJsonToRsao(text);
    EXPECT_EQ(rsaoToVisrJson(imported.rsao, imported.fields), text);

    // What the import holds: the room relative to the direct sound.
    const Rsao& r = imported.rsao;
    EXPECT_EQ(imported.fields.id, 3);
    EXPECT_EQ(imported.fields.channel, 5);
    EXPECT_EQ(*imported.fields.level, original.reflections[0].level);
    ASSERT_EQ(r.reflections.size(), original.reflections.size());
    EXPECT_EQ(r.reflections[0].time_of_arrival_s, 0.0);
    EXPECT_EQ(r.reflections[0].level, 1.0);
    for (std::size_t k = 1; k < r.reflections.size(); ++k) {
      const EarlyReflection &x = original.reflections[k], &y = r.reflections[k];
      EXPECT_NEAR(y.time_of_arrival_s, x.time_of_arrival_s - original.reflections[0].time_of_arrival_s, 1e-15);
      EXPECT_NEAR(y.level, x.level / original.reflections[0].level, 1e-15);
      EXPECT_NEAR(y.azimuth_rad, x.azimuth_rad, 1e-15);
      EXPECT_NEAR(y.elevation_rad, x.elevation_rad, 1e-15);
      EXPECT_EQ(y.distance_m, x.distance_m);
      EXPECT_EQ(y.confidence, x.confidence);
      EXPECT_EQ(y.sos.size(), 1u);
      EXPECT_EQ(y.sos[0].a2, x.sos[0].a2);
    }
    EXPECT_NEAR(r.late.onset_s, original.late.onset_s - original.reflections[0].time_of_arrival_s, 1e-15);
    EXPECT_EQ(r.late.attack_time_s, original.late.attack_time_s);
    for (std::size_t b = 0; b < 9; ++b) {
      EXPECT_EQ(r.late.bands[b].decay_constant_per_s, original.late.bands[b].decay_constant_per_s);
      EXPECT_NEAR(r.late.bands[b].level, original.late.bands[b].level / original.reflections[0].level, 1e-15);
      EXPECT_EQ(r.late.bands[b].reliable, original.late.bands[b].reliable);
      EXPECT_EQ(r.late.bands[b].reason, original.late.bands[b].reason);
      EXPECT_EQ(r.late.bands[b].first_decay_constant_per_s, original.late.bands[b].first_decay_constant_per_s);
      EXPECT_EQ(r.late.bands[b].second_decay_constant_per_s, original.late.bands[b].second_decay_constant_per_s);
      EXPECT_EQ(r.late.bands[b].second_share, original.late.bands[b].second_share);
    }
  }
}

TEST(RsaoVisrJson, WritesTheKeysVisrsParserReads) {
  const Rsao rsao = awkwardRsao(9);
  const nlohmann::json scene = nlohmann::json::parse(rsaoToVisrJson(rsao));
  const nlohmann::json& object = scene.at("objects").at(0);
  EXPECT_EQ(object.at("type"), "pointreverb");
  for (const char* key : {"id", "channels", "group", "priority", "level"}) EXPECT_TRUE(object.contains(key)) << key;
  EXPECT_NEAR(object.at("position").at("az").get<double>(), 0.1 * 180.0 / M_PI, 1e-12);
  const nlohmann::json& early = object.at("room").at("ereflect");
  ASSERT_EQ(early.size(), 4u);  // the direct sound is the object itself
  for (const char* key : {"delay", "level", "position", "biquadsos"}) EXPECT_TRUE(early[0].contains(key)) << key;
  for (const char* key : {"b0", "b1", "b2", "a0", "a1", "a2"}) EXPECT_TRUE(early[0].at("biquadsos").at(0).contains(key)) << key;
  const nlohmann::json& late = object.at("room").at("lreverb");
  // The nine band values: one comma-separated string per key, as VISR's parser splits it.
  for (const char* key : {"level", "attacktime", "decayconst"}) {
    ASSERT_TRUE(late.at(key).is_string()) << key;
    const std::string text = late.at(key).get<std::string>();
    EXPECT_EQ(std::count(text.begin(), text.end(), ','), 8) << key;
  }
  // Decay as VISR applies it: amplitude exp(decayconst t), negative.
  const std::string decays = late.at("decayconst").get<std::string>();
  EXPECT_EQ(decays.rfind('-', 0), 0u);
  EXPECT_DOUBLE_EQ(std::stod(decays), -rsao.late.bands[0].decay_constant_per_s);
  EXPECT_DOUBLE_EQ(late.at("delay").get<double>(), rsao.late.onset_s - rsao.reflections[0].time_of_arrival_s);
}

TEST(RsaoVisrJson, ReadsVisrStyleStringsAndNormalisesA0) {
  // Written the way VISR's property-tree writer writes: every value a string, a0 given.
  const std::string text = R"({"objects": [
    {"type": "plane", "id": "1"},
    {"type": "pointreverb", "id": "4", "channels": "2", "group": "0", "priority": "1", "level": "0.5",
     "position": {"az": "-90.0", "el": "30.0", "radius": "2.0"},
     "room": {
       "ereflect": [{"level": "0.25", "delay": "0.0100",
                     "position": {"az": "350.0", "el": "-10.0", "refdist": "3.5"},
                     "biquadsos": [{"b0": "2.0", "b1": "0.0", "b2": "0.0", "a0": "2.0", "a1": "-1.0", "a2": "0.5"}]}],
       "lreverb": {"delay": "0.020",
                   "level": "0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.05",
                   "attacktime": "0.030, 0.030, 0.030, 0.030, 0.030, 0.030, 0.030, 0.030, 0.030",
                   "decayconst": "-6.9, -6.9, -6.9, -6.9, -6.9, -6.9, -6.9, -13.8, -27.6"}}}]})";
  const VisrImport in = visrJsonToRsao(text);
  EXPECT_EQ(in.fields.id, 4);
  EXPECT_EQ(in.fields.channel, 2);
  EXPECT_EQ(in.fields.priority, 1);
  EXPECT_EQ(*in.fields.level, 0.5);
  const Rsao& r = in.rsao;
  ASSERT_EQ(r.reflections.size(), 2u);
  EXPECT_NEAR(r.reflections[0].azimuth_rad, -M_PI / 2, 1e-15);
  EXPECT_NEAR(r.reflections[0].elevation_rad, M_PI / 6, 1e-15);
  EXPECT_EQ(r.reflections[0].distance_m, 2.0);
  EXPECT_EQ(r.reflections[1].time_of_arrival_s, 0.01);
  EXPECT_EQ(r.reflections[1].distance_m, 3.5);
  EXPECT_NEAR(r.reflections[1].azimuth_rad, 350.0 * M_PI / 180.0, 1e-14);
  ASSERT_EQ(r.reflections[1].sos.size(), 1u);
  EXPECT_EQ(r.reflections[1].sos[0].b0, 1.0);  // divided by a0 = 2
  EXPECT_EQ(r.reflections[1].sos[0].a1, -0.5);
  EXPECT_EQ(r.reflections[1].sos[0].a2, 0.25);
  EXPECT_EQ(r.late.onset_s, 0.02);
  EXPECT_EQ(r.late.attack_time_s, 0.03);
  EXPECT_EQ(r.late.mixing_time_s, 0.05);
  ASSERT_EQ(r.late.bands.size(), 9u);
  EXPECT_EQ(r.late.bands[8].level, 0.05);
  EXPECT_EQ(r.late.bands[8].decay_constant_per_s, 27.6);
  EXPECT_NEAR(r.late.bands[0].t60_s, 3.0 * std::log(10.0) / 6.9, 1e-12);
  EXPECT_TRUE(r.late.bands[0].reliable);
  // Picked by id as well.
  EXPECT_EQ(visrJsonToRsao(text, 4).fields.id, 4);
  expectInputError([&] { visrJsonToRsao(text, 7); }, "no pointreverb object with id 7");
}

TEST(RsaoVisrJson, BadInputNamesTheKey) {
  const std::string good = rsaoToVisrJson(awkwardRsao(10), {}, -1);
  nlohmann::json scene = nlohmann::json::parse(good);
  auto broken = [&](auto edit) {
    nlohmann::json copy = scene;
    edit(copy["objects"][0]);
    return copy.dump();
  };
  expectInputError([&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["room"]["lreverb"].erase("decayconst"); })); },
                   "room.lreverb.decayconst: missing");
  expectInputError([&] { visrJsonToRsao(broken([](nlohmann::json& o) { o.erase("room"); })); }, "room: missing");
  expectInputError([&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["room"]["lreverb"]["level"] = "0.1, 0.2, 0.3"; })); },
                   "room.lreverb.level: has 3 values");
  expectInputError(
      [&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["room"]["lreverb"]["attacktime"] = nlohmann::json::array({0.1, 0.2}); })); },
      "room.lreverb.attacktime: has 2 values");
  expectInputError([&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["room"]["ereflect"][1]["delay"] = "soon"; })); },
                   "room.ereflect[1].delay: \"soon\" is not a number");
  expectInputError(
      [&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["room"]["lreverb"]["level"] = "0.1, 0.1, x, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1"; })); },
      "room.lreverb.level[2]: ' x' is not a number");
  expectInputError([&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["room"]["ereflect"][0]["biquadsos"][0].erase("b1"); })); },
                   "room.ereflect[0].biquadsos[0].b1: missing");
  expectInputError([&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["position"].erase("az"); o["position"].erase("el"); })); },
                   "position.x: missing");
  expectInputError(
      [&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["room"]["lreverb"]["decayconst"] = "1, -1, -1, -1, -1, -1, -1, -1, -1"; })); },
      "room.lreverb.decayconst[0]: must be negative");
  expectInputError([&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["type"] = "point"; })); }, "no object of type pointreverb");
  expectInputError([&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["room_reverb"]["band_two_slopes"][1] = 3; })); },
                   "room_reverb.band_two_slopes[1]: must be [first decay constant, second decay constant, second share]");
  expectInputError(
      [&] { visrJsonToRsao(broken([](nlohmann::json& o) { o["room_reverb"]["band_two_slopes"][1] = {5.0, -1.0, 0.2}; })); },
      "room_reverb.band_two_slopes[1]: needs positive decay constants");
  expectInputError([&] { visrJsonToRsao("{\"objects\": ["); }, "not valid JSON");
  // Valid JSON syntax, but a number no double holds: nlohmann throws out_of_range, not
  // parse_error, and that too must reach the user as InputError (fuzz/fuzz_visr_json.cpp).
  expectInputError([&] { visrJsonToRsao("{\"objects\": [{\"level\": 13.0e444}]}"); },
                   "VISR JSON: not valid JSON ([json.exception.out_of_range.406] number overflow parsing '13.0e444')");
}

TEST(RsaoVisrJson, RefusesWhatVisrCannotHold) {
  Rsao r = awkwardRsao(11);
  r.reflections[2].sos.assign(11, BiquadSection{});
  expectInputError([&] { rsaoToVisrJson(r); }, "at most 10");
  r = awkwardRsao(11);
  r.late.bands.pop_back();
  expectInputError([&] { rsaoToVisrJson(r); }, "nine octave bands");
  r = awkwardRsao(11);
  r.reflections.clear();
  expectInputError([&] { rsaoToVisrJson(r); }, "no direct sound");
  r = awkwardRsao(11);
  r.late.bands[4].decay_constant_per_s = 0.0;
  expectInputError([&] { rsaoToVisrJson(r); }, "positive decay constant");
}
