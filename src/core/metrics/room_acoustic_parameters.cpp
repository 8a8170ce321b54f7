#include "room_reverb/metrics/room_acoustic_parameters.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/band_filter_bank.h"
#include "room_reverb/common/error.h"
#include "room_reverb/metrics/energy_decay.h"
#include "room_reverb/metrics/onset.h"

namespace room_reverb::core {
namespace {

double energyOf(const std::vector<float>& x, std::size_t first, std::size_t last, double fs) {
  double sum = 0.0;
  for (std::size_t n = first; n < std::min(last, x.size()); ++n) sum += static_cast<double>(x[n]) * x[n];
  return sum / fs;
}

void addReason(AcousticParameters& p, const std::string& reason) {
  p.reliable = false;
  if (!p.reason.empty()) p.reason += "; ";
  p.reason += reason;
}

std::string rangeReason(const char* quantity, double needed_db, double have_db) {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(1);
  os << quantity << " needs " << needed_db << " dB of decay above the noise floor, this has "
     << have_db << " dB";
  return os.str();
}

// The direct sound: from the onset (or 2.5 ms before the peak, if earlier) to 2.5 ms after
// the peak, the largest sample in the 2.5 ms after the onset.
struct DirectWindow {
  std::size_t first = 0;
  std::size_t last = 0;  // one past
};

DirectWindow directWindow(const std::vector<float>& rir, std::size_t onset, double fs,
                          double half_window_s) {
  // The direct sound's peak follows the onset within the half window; a later, stronger
  // peak (a focused reflection, or a loudspeaker pointing away) is not the direct sound.
  const auto half = static_cast<std::size_t>(std::lround(half_window_s * fs));
  std::size_t peak = onset;
  for (std::size_t n = onset; n < std::min(rir.size(), onset + half + 1); ++n) {
    if (std::abs(rir[n]) > std::abs(rir[peak])) peak = n;
  }
  DirectWindow w;
  w.first = std::min(onset, peak > half ? peak - half : 0);
  w.last = std::min(rir.size(), peak + half + 1);
  return w;
}

// Every parameter of one (band-filtered) signal. `direct` is the same band of the direct
// sound alone; the DRR sets it against the rest of the band's energy.
// `band_width_hz`: 0 for broadband.
AcousticParameters analyseSignal(const std::vector<float>& signal, const std::vector<float>& direct,
                                 std::size_t onset, double fs, double band_width_hz,
                                 double direct_window_s) {
  AcousticParameters p;
  const EnergyDecay decay(signal, onset, fs);
  if (!decay.valid()) {
    addReason(p, decay.lundeby().failure);
    return p;
  }
  p.decay_range_db = decay.decayRangeDb();
  if (p.decay_range_db < kRangeNeededForEdtDb) {
    addReason(p, rangeReason("every parameter", kRangeNeededForEdtDb, p.decay_range_db));
    return p;
  }

  const double edt = decay.decayTimeS(0.0, -10.0);
  if (edt > 0.0) p.edt_s = edt; else addReason(p, "EDT: the decay never falls 10 dB");
  if (p.decay_range_db >= kRangeNeededForT20Db) {
    const double t20 = decay.decayTimeS(-5.0, -25.0);
    if (t20 > 0.0) p.t20_s = t20; else addReason(p, "T20: no decay from -5 to -25 dB");
  } else {
    addReason(p, rangeReason("T20", kRangeNeededForT20Db, p.decay_range_db));
  }
  if (p.decay_range_db >= kRangeNeededForT30Db) {
    const double t30 = decay.decayTimeS(-5.0, -35.0);
    if (t30 > 0.0) p.t30_s = t30; else addReason(p, "T30: no decay from -5 to -35 dB");
  } else {
    addReason(p, rangeReason("T30", kRangeNeededForT30Db, p.decay_range_db));
  }

  // Energy ratios (ISO 3382-1 A.2): early energy up to 50 / 80 ms after the onset.
  const double total = decay.energyAfter(0.0);
  const double after50 = decay.energyAfter(0.050);
  const double after80 = decay.energyAfter(0.080);
  p.c50_db = 10.0 * std::log10((total - after50) / after50);
  p.c80_db = 10.0 * std::log10((total - after80) / after80);
  p.d50 = (total - after50) / total;
  p.ts_s = decay.centreTimeS();

  // DRR: the band's energy before the onset (filter spread of the direct sound) belongs to
  // the total too.
  // A band filter smears the direct sound over about 1/bandwidth; when that exceeds the
  // direct window, the window cannot hold the band's direct sound and the ratio would be
  // an artefact of the filter.
  if (band_width_hz > 0.0 && 1.0 / band_width_hz > direct_window_s) {
    std::ostringstream os;
    os.setf(std::ios::fixed);
    os.precision(1);
    os << "DRR: the band rings for " << 1000.0 / band_width_hz << " ms, longer than the "
       << 1000.0 * direct_window_s << " ms direct-sound window";
    addReason(p, os.str());
    return p;
  }
  const double pre_onset = energyOf(signal, 0, onset, fs);
  const double direct_energy = energyOf(direct, 0, direct.size(), fs);
  const double reverberant = pre_onset + total - direct_energy;
  if (direct_energy > 0.0 && reverberant > 0.0) {
    p.drr_db = 10.0 * std::log10(direct_energy / reverberant);
  } else {
    addReason(p, "DRR: no reverberant energy beside the direct sound");
  }
  return p;
}

}  // namespace

MetricsReport computeRoomAcousticParameters(const std::vector<float>& rir, double fs,
                                            const MetricsOptions& options) {
  if (!(fs >= kMinSampleRateHz && fs <= kMaxSampleRateHz)) {
    std::ostringstream os;
    os << "sample rate " << fs << " Hz is outside the accepted " << kMinSampleRateHz << "-" << kMaxSampleRateHz << " Hz";
    throw InputError(os.str());
  }
  const auto min_length = static_cast<std::size_t>(std::ceil(0.010 * fs));
  if (rir.size() < min_length) {
    std::ostringstream os;
    os << "the impulse response is " << rir.size() << " samples long; at least 10 ms ("
       << min_length << " samples) is needed";
    throw InputError(os.str());
  }
  for (std::size_t n = 0; n < rir.size(); ++n) {
    if (!std::isfinite(rir[n])) {
      std::ostringstream os;
      os << "sample " << n << " of the impulse response is not finite";
      throw InputError(os.str());
    }
  }

  MetricsReport report;
  report.sample_rate_hz = fs;
  report.resolution = options.resolution;
  report.onset_sample = findDirectSoundOnset(rir, options.onset_threshold_db);
  report.onset_s = report.onset_sample / fs;

  const DirectWindow window = directWindow(rir, report.onset_sample, fs, options.direct_half_window_s);
  std::vector<float> direct(rir.size(), 0.0f);
  std::copy(rir.begin() + window.first, rir.begin() + window.last, direct.begin() + window.first);

  const double direct_window_s = static_cast<double>(window.last - window.first) / fs;
  report.broadband = analyseSignal(rir, direct, report.onset_sample, fs, 0.0, direct_window_s);

  const BandFilterBank bank(standardBands(options.resolution), fs);
  const auto band_signals = bank.split(rir);
  const auto band_direct = bank.split(direct);
  const double bandwidth = options.recorded_bandwidth_hz > 0.0 ? std::min(options.recorded_bandwidth_hz, 0.5 * fs) : 0.5 * fs;
  for (std::size_t b = 0; b < bank.bands().size(); ++b) {
    const FrequencyBand& band = bank.bands()[b];
    AcousticParameters p;
    if (band.center_hz >= bandwidth) {
      std::ostringstream os;
      os << "the band lies above the recording's bandwidth (" << bandwidth << " Hz)";
      addReason(p, os.str());
    } else {
      p = analyseSignal(band_signals[b], band_direct[b], report.onset_sample, fs,
                        band.upper_hz - band.lower_hz, direct_window_s);
    }
    p.nominal_hz = band.nominal_hz;
    p.center_hz = band.center_hz;
    report.bands.push_back(p);
  }
  return report;
}

}  // namespace room_reverb::core
