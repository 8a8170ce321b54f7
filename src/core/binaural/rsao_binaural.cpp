#include "room_reverb/binaural/rsao_binaural.h"

#include <Eigen/LU>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

#include "diffuse_ear_mix.h"
#include "room_reverb/audio/convolution.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/late_noise.h"
#include "room_reverb/rsao/reflection_tap.h"
#include "room_reverb/rsao/rsao_render_input.h"

namespace room_reverb::core {
namespace {

const std::string kContext = "binaural RSAO";
// Off the internal rate by more than this, the set was not loaded for this renderer.
constexpr double kRateToleranceHz = 1e-6;
// head_in_rig^T head_in_rig may differ from the identity by rounding only.
constexpr double kOrthonormalityTolerance = 1e-6;

void checkInput(const Rsao& rsao, const HrtfSet& hrtfs, const RsaoBinauralOptions& options) {
  if (rsao.reflections.empty()) {
    throw InputError(kContext + ": the object has no direct sound (no reflections): estimate it from an RIR "
                                "with a direct sound, or give reflections[0]");
  }
  if (std::abs(hrtfs.sampleRateHz() - kInternalSampleRateHz) > kRateToleranceHz) {
    std::ostringstream os;
    os << kContext << ": the HRTF set is at " << hrtfs.sampleRateHz()
       << " Hz; load it at 48000 Hz (HrtfSet::loadSofa resamples to 48 kHz by default)";
    throw InputError(os.str());
  }
  const Eigen::Matrix3d& r = options.head_in_rig;
  if (!r.allFinite() || (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > kOrthonormalityTolerance ||
      r.determinant() < 0.0) {
    throw InputError(kContext + ": head_in_rig is not a proper rotation (orthonormal with determinant +1)");
  }
  checkRenderInput(rsao, options.resynthesis, kContext);
}

void addAt(const std::vector<float>& signal, long first, std::vector<float>& out) {
  for (std::size_t i = 0; i < signal.size(); ++i) {
    const long n = first + static_cast<long>(i);
    if (n < 0) continue;
    if (static_cast<std::size_t>(n) >= out.size()) break;
    out[static_cast<std::size_t>(n)] += signal[i];
  }
}

// Each tap (reflection_tap.h, as the resynthesis' W) through the HRIR pair of its
// direction in the head frame.
void addEarlyPart(const Rsao& rsao, const HrtfSet& hrtfs, const RsaoBinauralOptions& o, AudioBuffer& out) {
  const ResynthesisOptions& r = o.resynthesis;
  for (std::size_t k = 0; k < rsao.reflections.size(); ++k) {
    const EarlyReflection& reflection = rsao.reflections[k];
    const ReflectionTap tap = shapeReflectionTap(reflection, k, r.analysis_window_s, r.reflection_response_s, kContext);
    if (tap.gain == 0.0) continue;
    std::vector<float> scaled(tap.samples.size());
    for (std::size_t i = 0; i < scaled.size(); ++i) scaled[i] = static_cast<float>(tap.gain * tap.samples[i]);
    const Hrir hrir = hrtfs.interpolated(o.head_in_rig.transpose() * reflectionDirection(reflection));
    addAt(fftConvolve(scaled, hrir.left), tap.first_sample, out.channels[0]);
    addAt(fftConvolve(scaled, hrir.right), tap.first_sample, out.channels[1]);
  }
}

// Each ear: a resynthesis of the late part (late_noise.h) whose band noises are mixed to
// the set's diffuse-field coherence before they are shaped, and whose band targets are the
// W targets times the ear's diffuse-field power. Mixing the stationary noises first keeps
// the shaped envelopes exact (a filter applied afterwards would smear the onset backwards)
// and lets the leakage correction and envelope matching work on each ear as it will be
// analysed.
void addLatePart(const LateReverb& late, const DiffuseFieldSpectrum& diffuse_field, const RsaoBinauralOptions& o,
                 AudioBuffer& out) {
  const DiffuseFieldBands field = diffuseFieldBands(diffuse_field);
  LateNoiseSynthesizer synthesizer(out.frameCount(), o.resynthesis);
  std::vector<std::vector<float>> first = synthesizer.drawBandNoises();
  std::vector<std::vector<float>> second = synthesizer.drawBandNoises();
  synthesizer.flattenEnvelopes(first);
  synthesizer.flattenEnvelopes(second);
  const std::vector<std::vector<double>> w_target = synthesizer.targetPowers(late);
  const std::vector<std::vector<std::vector<float>>> ears = mixEarBandNoises(first, second, field.coherence);
  for (std::size_t ear = 0; ear < 2; ++ear) {
    const std::vector<double>& power = ear == 0 ? field.power_left : field.power_right;
    std::vector<std::vector<double>> target = w_target;
    for (std::size_t b = 0; b < target.size(); ++b) {
      for (double& v : target[b]) v *= power[b];
    }
    const std::vector<float> x = synthesizer.shape(target, ears[ear]);
    for (std::size_t n = 0; n < out.frameCount(); ++n) out.channels[ear][n] += x[n];
  }
}

}  // namespace

AudioBuffer renderRsaoBinaural(const Rsao& rsao, const HrtfSet& hrtfs, const RsaoBinauralOptions& options) {
  checkInput(rsao, hrtfs, options);
  const bool late = options.resynthesis.include_late && !rsao.late.bands.empty();
  // The spectrum only when there is a late part to shape with it.
  return renderRsaoBinaural(rsao, hrtfs, late ? diffuseFieldSpectrum(hrtfs) : DiffuseFieldSpectrum{}, options);
}

AudioBuffer renderRsaoBinaural(const Rsao& rsao, const HrtfSet& hrtfs, const DiffuseFieldSpectrum& diffuse_field,
                               const RsaoBinauralOptions& options) {
  checkInput(rsao, hrtfs, options);
  const bool late = options.resynthesis.include_late && !rsao.late.bands.empty();
  if (late && !(diffuse_field.bin_spacing_hz > 0.0 && diffuse_field.power_left.size() > 1 &&
                diffuse_field.power_right.size() == diffuse_field.power_left.size() &&
                diffuse_field.coherence.size() == diffuse_field.power_left.size())) {
    throw InputError(kContext + ": the diffuse-field spectrum is empty or inconsistent: pass diffuseFieldSpectrum(hrtfs)");
  }
  AudioBuffer out = makeSilentBuffer(2, renderFrameCount(rsao, options.resynthesis, kContext), kInternalSampleRateHz);
  if (options.resynthesis.include_early) addEarlyPart(rsao, hrtfs, options, out);
  if (late) addLatePart(rsao.late, diffuse_field, options, out);
  return out;
}

}  // namespace room_reverb::core
