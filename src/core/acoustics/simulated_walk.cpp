#include "room_reverb/acoustics/simulated_walk.h"

#include <algorithm>
#include <array>

#include "room_reverb/acoustics/propagation.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

SimulatedWalk::SimulatedWalk(AcousticScene scene, const Eigen::Vector3d& source_m,
                             const Eigen::Vector3d& reference_listener_m, const SimulationSettings& settings)
    : scene_(std::move(scene)), source_m_(source_m), reference_m_(reference_listener_m), settings_(settings) {
  const SimulationResult reference = simulateRoom(scene_, source_m_, reference_m_, settings_);
  synthesis_ = simulationSynthesisOptions(scene_, settings_);
  late_ = synthesizeLatePart(reference, synthesis_);
  makeThirdViews();
}

void SimulatedWalk::makeThirdViews() {
  if (settings_.bands != BandResolution::kThirdOctave) return;
  for (int k = 0; k < 3; ++k) third_views_.push_back(scene_.thirdOctaveBands(k));
}

SimulatedWalk::SimulatedWalk(AcousticScene scene, const Eigen::Vector3d& source_m,
                             const Eigen::Vector3d& reference_listener_m, const SimulationSettings& settings,
                             AudioBuffer late)
    : scene_(std::move(scene)), source_m_(source_m), reference_m_(reference_listener_m), settings_(settings),
      late_(std::move(late)) {
  validateAudioBuffer(late_, "the late part");
  if (late_.sample_rate_hz != kInternalSampleRateHz ||
      late_.channelCount() != static_cast<std::size_t>(ambisonicChannelCount(settings_.ambisonic_order))) {
    throw InputError("the late part must be AmbiX of order " + std::to_string(settings_.ambisonic_order) + " at 48000 Hz");
  }
  if (!source_m_.allFinite()) throw InputError("the source position is not finite");
  scene_.requireInside(source_m_, "source");
  requireListener(reference_m_);
  synthesis_ = simulationSynthesisOptions(scene_, settings_);
  makeThirdViews();
}

void SimulatedWalk::requireListener(const Eigen::Vector3d& listener_m) const {
  if (!listener_m.allFinite()) throw InputError("the listener position is not finite");
  scene_.requireInside(listener_m, "listener");
  if ((listener_m - source_m_).norm() < 0.05) throw InputError("the listener is closer than 5 cm to the source");
}

std::vector<SpecularPath> SimulatedWalk::pathsAt(const Eigen::Vector3d& listener_m) const {
  requireListener(listener_m);
  return computeImageSources(scene_, source_m_, listener_m, PropagationModel::from(settings_.air, settings_.directivity),
                             imageSourceOptionsFor(settings_));
}

AudioBuffer SimulatedWalk::earlyAt(const Eigen::Vector3d& listener_m) const {
  const std::vector<SpecularPath> paths = pathsAt(listener_m);
  double last_s = 0.0;
  for (const SpecularPath& p : paths) last_s = std::max(last_s, p.delay_s);
  SynthesisOptions options = synthesis_;
  // To the end of the last path's band-shaping FIR, which is centred on its arrival.
  const double fir_half_s = static_cast<double>(kPathTapLength / 2 + 1) / options.sample_rate_hz;
  options.duration_s = std::min(last_s + fir_half_s, settings_.duration_s);
  if (settings_.bands != BandResolution::kThirdOctave) return synthesizeImpulseResponse(paths, nullptr, options);
  // In third octaves each third's view gives the same arrivals with its own gains.
  std::array<std::vector<SpecularPath>, 3> thirds;
  for (std::size_t k = 0; k < 3; ++k) {
    const AcousticScene& view = third_views_[k];
    thirds[k] = computeImageSources(view, source_m_, listener_m,
                                    PropagationModel::from(settings_.air, settings_.directivity, view.bandCentresHz()),
                                    imageSourceOptionsFor(settings_));
  }
  return synthesizeThirdOctaveImpulseResponse({&thirds[0], &thirds[1], &thirds[2]}, {nullptr, nullptr, nullptr}, options);
}

AudioBuffer SimulatedWalk::responseAt(const Eigen::Vector3d& listener_m) const {
  return responseWith(earlyAt(listener_m));
}

AudioBuffer SimulatedWalk::responseWith(const AudioBuffer& early) const {
  if (early.channelCount() != late_.channelCount()) {
    throw InputError("simulated walk: an early part of " + std::to_string(early.channelCount()) +
                     " channels for a late part of " + std::to_string(late_.channelCount()));
  }
  AudioBuffer whole = late_;
  // earlyAt is never longer than the settings' duration, which is the late part's length.
  for (std::size_t c = 0; c < whole.channelCount(); ++c) {
    const std::size_t frames = std::min(early.frameCount(), whole.frameCount());
    for (std::size_t n = 0; n < frames; ++n) whole.channels[c][n] += early.channels[c][n];
  }
  return whole;
}

}  // namespace room_reverb::core
