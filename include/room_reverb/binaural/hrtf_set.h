#pragma once
// A set of head-related impulse responses: one left/right pair per measured direction,
// at one sample rate. Directions are unit vectors in the `head` frame (REP 103: x ahead,
// y left, z up), so azimuth +90 deg is the listener's left.
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

struct Hrir {
  std::vector<float> left;
  std::vector<float> right;
};

// Where the direct sound starts in each ear's HRIR, in samples with sub-sample accuracy
// (the first crossing of -20 dB below the peak of the band-limited waveform).
struct HrirOnset {
  double left;
  double right;
};

class HrtfSet {
 public:
  // Reads a SOFA file of the SimpleFreeFieldHRIR convention with libmysofa and resamples
  // it to `target_rate_hz`. Throws InputError for a missing, corrupt or other-convention
  // file. notes() says what was changed on the way (resampling, normalisation).
  static HrtfSet loadSofa(const std::string& path,
                          double target_rate_hz = kInternalSampleRateHz);

  // The bundled KU100 set: $ROOM_REVERB_HRTF when set, else data/hrtf/FHK_HRIR_L2354.sofa
  // of the package.
  static std::string defaultSofaPath();

  // From memory (tests and synthetic head models). Every HRIR has the same length;
  // directions are normalised. Throws InputError on an empty or inconsistent set.
  HrtfSet(double sample_rate_hz, std::vector<Eigen::Vector3d> directions,
          std::vector<Hrir> hrirs, std::string description = "");

  double sampleRateHz() const { return sample_rate_hz_; }
  std::size_t size() const { return directions_.size(); }
  std::size_t length() const { return hrirs_.front().left.size(); }
  const Eigen::Vector3d& direction(std::size_t i) const { return directions_[i]; }
  const std::vector<Eigen::Vector3d>& directions() const { return directions_; }
  const Hrir& hrir(std::size_t i) const { return hrirs_[i]; }
  const std::string& description() const { return description_; }
  const std::vector<std::string>& notes() const { return notes_; }
  const HrirOnset& onset(std::size_t i) const { return onsets_[i]; }

  // Index of the measured direction with the largest dot product with `direction` (any
  // length; InputError if zero or not finite, as for interpolated()).
  std::size_t nearest(const Eigen::Vector3d& direction) const;
  // An HRIR for any direction: the measured directions around it weighted by their
  // closeness, after their onsets are aligned (time-aligned interpolation, so the
  // interaural delay is interpolated rather than comb-filtered), then the interpolated
  // delay put back with sub-sample accuracy.
  Hrir interpolated(const Eigen::Vector3d& direction) const;

 private:
  double sample_rate_hz_;
  std::vector<Eigen::Vector3d> directions_;
  std::vector<Hrir> hrirs_;
  std::string description_;
  std::vector<std::string> notes_;
  // The directions as rows, so that nearest() is one matrix-vector product.
  Eigen::MatrixX3d direction_rows_;
  std::vector<HrirOnset> onsets_;
};

}  // namespace room_reverb::core
