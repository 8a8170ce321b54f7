#include "room_reverb/rsao/rsao_resynthesis.h"

#include <cmath>
#include <vector>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/rsao/late_noise.h"
#include "room_reverb/rsao/reflection_tap.h"
#include "room_reverb/rsao/rsao_render_input.h"

namespace room_reverb::core {
namespace {

constexpr double kFs = kInternalSampleRateHz;

// The tap (reflection_tap.h) encoded with sn3dHarmonics(1, direction).
void addReflection(const EarlyReflection& r, std::size_t k, const ResynthesisOptions& o, AudioBuffer& out) {
  const ReflectionTap tap = shapeReflectionTap(r, k, o.analysis_window_s, o.reflection_response_s, "resynthesis");
  if (tap.gain == 0.0) return;
  const std::vector<double> harmonics = sn3dHarmonics(1, reflectionDirection(r));
  for (std::size_t i = 0; i < tap.samples.size(); ++i) {
    const long n = tap.first_sample + static_cast<long>(i);
    if (n < 0) continue;
    if (static_cast<std::size_t>(n) >= out.frameCount()) break;
    for (std::size_t c = 0; c < 4; ++c) {
      out.channels[c][static_cast<std::size_t>(n)] += static_cast<float>(tap.gain * harmonics[c] * tap.samples[i]);
    }
  }
}

// Four independent draws of the late part (late_noise.h), one per channel.
void addLateReverb(const LateReverb& late, const ResynthesisOptions& o, AudioBuffer& out) {
  LateNoiseSynthesizer synthesizer(out.frameCount(), o);
  const std::vector<std::vector<double>> target = synthesizer.targetPowers(late);
  // Diffuse field in SN3D: E[X^2] = E[Y^2] = E[Z^2] = E[W^2] / 3, all mutually uncorrelated.
  const double channel_gain[4] = {1.0, 1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0)};
  for (std::size_t c = 0; c < 4; ++c) {
    const std::vector<float> x = synthesizer.shape(target, synthesizer.drawBandNoises());
    for (std::size_t n = 0; n < out.frameCount(); ++n) out.channels[c][n] += static_cast<float>(channel_gain[c] * x[n]);
  }
}

}  // namespace

AudioBuffer resynthesizeRsao(const Rsao& rsao, const ResynthesisOptions& options) {
  checkRenderInput(rsao, options, "resynthesis");
  AudioBuffer out = makeSilentBuffer(4, renderFrameCount(rsao, options, "resynthesis"), kFs);
  if (options.include_early) {
    for (std::size_t k = 0; k < rsao.reflections.size(); ++k) addReflection(rsao.reflections[k], k, options, out);
  }
  if (options.include_late && !rsao.late.bands.empty()) addLateReverb(rsao.late, options, out);
  return out;
}

}  // namespace room_reverb::core
