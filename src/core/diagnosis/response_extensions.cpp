#include "room_reverb/diagnosis/response_extensions.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "room_reverb/acoustics/propagation.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/audio/crossover.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

void addCoupledDecay(std::vector<float>& omni, double sample_rate_hz, std::size_t onset_sample,
                     const CoupledDecay& decay, std::uint32_t seed) {
  if (!(decay.t60_s > 0.0)) throw InputError("coupled decay: the decay time must be positive");
  const auto half = static_cast<std::size_t>(0.001 * sample_rate_hz);
  double direct = 0.0;
  for (std::size_t n = onset_sample > half ? onset_sample - half : 0; n < std::min(omni.size(), onset_sample + half); ++n) {
    direct += static_cast<double>(omni[n]) * omni[n];
  }
  // Energy envelope P0 exp(-13.8 t / T60) per second, P0 = direct * 10^(L/10): samples of
  // unit-variance noise scaled by sqrt(P / fs) carry that energy per second.
  const double p0 = direct * std::pow(10.0, decay.level_db / 10.0);
  const double rate = 3.0 * std::log(10.0) / decay.t60_s;  // amplitude decay per second
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  for (std::size_t n = onset_sample; n < omni.size(); ++n) {
    const double t = static_cast<double>(n - onset_sample) / sample_rate_hz;
    omni[n] += static_cast<float>(std::sqrt(p0 / sample_rate_hz) * std::exp(-rate * t)) * noise(rng);
  }
}

double modalCrossoverHz(const AcousticScene& scene, const AirConditions& air) {
  const OctaveBandValues t60 = eyringReverberationTimes(scene, air);
  return schroederFrequencyHz(0.5 * (t60[3] + t60[4]), scene.volumeM3());  // 500 Hz, 1 kHz
}

ModalRoom modalRoomFor(const AcousticScene& scene, const AirConditions& air) {
  return modalRoomFromScene(scene, speedOfSoundMPerS(air.temperature_c));
}

void applyResponseExtensions(AudioBuffer& response, const ModelExtension& extension, const ModalRoom* modal_room,
                             const MeasurementPair& pair, double direct_delay_s, std::uint32_t seed) {
  if (extension.modes) {
    if (!modal_room) throw InputError("the modal extension needs the room's modes");
    const double crossover = extension.modes->crossover_hz;
    ModalSynthesisOptions options;
    options.sample_rate_hz = response.sample_rate_hz;
    options.frames = response.frameCount();
    options.ambisonic_order = response.channelCount() >= 4 ? 1 : 0;
    // Modes up to a third above the crossover's upper edge (it spans an octave): those
    // beyond add only the tails of their resonance curves below it.
    options.max_frequency_hz = std::min(1.3 * std::sqrt(2.0) * crossover, 0.45 * response.sample_rate_hz);
    options.damping_scale = extension.modes->damping_scale;
    const AudioBuffer modal = synthesizeRoomModes(*modal_room, pair.source_m, pair.receiver_m, options);
    response = joinAtCrossover(modal, response, crossover);
  }
  if (extension.coupled && !response.channels.empty()) {
    const auto onset = static_cast<std::size_t>(std::lround(direct_delay_s * response.sample_rate_hz));
    addCoupledDecay(response.channels.front(), response.sample_rate_hz, onset, *extension.coupled, seed);
  }
}

}  // namespace room_reverb::core
