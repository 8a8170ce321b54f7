// Metrics on the bundled measured RIRs: plausible, complete where the data allows, and
// identical from run to run.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "room_reverb/audio/audio_file.h"
#include "room_reverb/metrics/impulse_response_metrics.h"

using namespace room_reverb::core;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> bundledRirs() {
  std::vector<std::string> files;
  for (const char* dir : {"data/rirs/bformat", "data/rirs/omni"}) {
    for (const auto& entry : fs::directory_iterator(fs::path(ROOM_REVERB_SOURCE_DIR) / dir)) {
      if (entry.path().extension() == ".wav") files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

TEST(MetricsOnMeasuredRirs, EveryBundledRirGivesPlausibleValues) {
  const auto files = bundledRirs();
  ASSERT_EQ(files.size(), 6u);
  for (const auto& file : files) {
    const AudioBuffer rir = readAudioFile(file);
    const MetricsReport report = analyseImpulseResponse(rir, 0);
    const auto& broadband = report.broadband;
    ASSERT_TRUE(broadband.t20_s) << file << ": " << broadband.reason;
    EXPECT_GT(*broadband.t20_s, 0.1) << file;
    EXPECT_LT(*broadband.t20_s, 10.0) << file;
    EXPECT_GT(broadband.decay_range_db, 35.0) << file;
    // Every B-format room has a measurable T20 and sensible ratios from 125 Hz to 8 kHz;
    // the hand clap has little energy below 1 kHz.
    const bool clap = file.find("clap") != std::string::npos;
    for (const auto& band : report.bands) {
      if (band.nominal_hz < (clap ? 1000 : 125) || band.nominal_hz > 8000) continue;
      ASSERT_TRUE(band.t20_s) << file << " " << band.nominal_hz << ": " << band.reason;
      EXPECT_GT(*band.t20_s, 0.1) << file << " " << band.nominal_hz;
      EXPECT_LT(*band.t20_s, 10.0) << file << " " << band.nominal_hz;
      ASSERT_TRUE(band.edt_s && band.c80_db && band.d50) << file << " " << band.nominal_hz;
      EXPECT_GT(*band.d50, 0.0);
      EXPECT_LT(*band.d50, 1.0);
      EXPECT_GT(*band.c80_db, -15.0);
      EXPECT_LT(*band.c80_db, 25.0);
      // T20 and T30 of one decay agree where both exist.
      if (band.t30_s) {
        EXPECT_NEAR(*band.t30_s / *band.t20_s, 1.0, 0.25) << file << " " << band.nominal_hz;
      }
    }
  }
}

TEST(MetricsOnMeasuredRirs, ValuesDoNotChangeBetweenRuns) {
  const AudioBuffer rir = readAudioFile((fs::path(ROOM_REVERB_SOURCE_DIR) / "data/rirs/bformat/dixon_studio_theatre_r1.wav").string());
  const MetricsReport a = analyseImpulseResponse(rir, 0);
  const MetricsReport b = analyseImpulseResponse(rir, 0);
  ASSERT_EQ(a.bands.size(), b.bands.size());
  for (std::size_t i = 0; i < a.bands.size(); ++i) {
    EXPECT_EQ(a.bands[i].t20_s, b.bands[i].t20_s);
    EXPECT_EQ(a.bands[i].t30_s, b.bands[i].t30_s);
    EXPECT_EQ(a.bands[i].edt_s, b.bands[i].edt_s);
    EXPECT_EQ(a.bands[i].c80_db, b.bands[i].c80_db);
  }
}

TEST(MetricsOnMeasuredRirs, ClapAt44kHzIsResampledAndBandsAboveNyquistFlagged) {
  const AudioBuffer clap = readAudioFile((fs::path(ROOM_REVERB_SOURCE_DIR) / "data/rirs/omni/clap_seminar_room.wav").string());
  ASSERT_EQ(clap.sample_rate_hz, 44100.0);
  const MetricsReport report = analyseImpulseResponse(clap, 0);
  EXPECT_EQ(report.sample_rate_hz, 48000.0);
  MetricsOptions narrow;
  narrow.recorded_bandwidth_hz = 6000.0;
  const MetricsReport limited = analyseImpulseResponse(clap, 0, narrow);
  EXPECT_FALSE(limited.bands[7].t20_s.has_value());  // 8 kHz above the 6 kHz limit
  EXPECT_NE(limited.bands[7].reason.find("bandwidth"), std::string::npos);
}
