#pragma once
// Room-acoustic parameters of ISO 3382-1:2009 from an impulse response, per band and
// broadband: reverberation times T20, T30 and EDT; clarity C50, C80; definition D50;
// centre time Ts; direct-to-reverberant ratio.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::core {

struct AcousticParameters {
  double nominal_hz = 0.0;  // band label; 0 for broadband
  double center_hz = 0.0;   // exact centre; 0 for broadband
  // Each value is empty when it cannot be measured; `reason` then says why.
  std::optional<double> t20_s, t30_s, edt_s, c50_db, c80_db, d50, ts_s, drr_db;
  double decay_range_db = 0.0;  // peak-to-noise range of the decay (ISO 3382-1 5.3.3)
  bool reliable = true;         // false when any value above is empty
  std::string reason;
};

struct MetricsOptions {
  BandResolution resolution = BandResolution::kOctave;
  double onset_threshold_db = 20.0;  // ISO 3382-1 annex A
  // Half-width of the direct-sound window around the peak, for the DRR. 2.5 ms is the
  // usual choice: long enough for a loudspeaker's own response, short enough to exclude
  // the first floor reflection at typical heights.
  double direct_half_window_s = 0.0025;
  // Upper limit of the recording's content (its original Nyquist frequency when it was
  // resampled). Bands centred above it are reported as unavailable. <= 0: no limit.
  double recorded_bandwidth_hz = 0.0;
};

struct MetricsReport {
  double sample_rate_hz = 0.0;
  std::size_t onset_sample = 0;
  double onset_s = 0.0;
  BandResolution resolution = BandResolution::kOctave;
  std::vector<AcousticParameters> bands;
  AcousticParameters broadband;
};

// Throws InputError for a response that is too short (< 10 ms), silent or not finite.
MetricsReport computeRoomAcousticParameters(const std::vector<float>& rir, double sample_rate_hz,
                                            const MetricsOptions& options = {});

// ISO 3382-1 5.3.3: the decay range each quantity needs above the noise floor.
constexpr double kRangeNeededForT30Db = 45.0;
constexpr double kRangeNeededForT20Db = 35.0;
// EDT spans 10 dB; with the same 10 dB margin to the noise as T20/T30 have, 20 dB. The
// energy ratios (C, D, Ts, DRR) are held to the same range.
constexpr double kRangeNeededForEdtDb = 20.0;

}  // namespace room_reverb::core
