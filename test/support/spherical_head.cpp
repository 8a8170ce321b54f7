#include "spherical_head.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>

#include "room_reverb/audio/fft.h"
#include "room_reverb/binaural/loudspeaker_layout.h"

namespace room_reverb::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRate = 48000.0;
// Synthesised on a long FFT frame, then cut to the HRIR length, so that neither the
// fractional delay's sinc tails nor the shadow filter's decay wrap around.
constexpr std::size_t kSynthesisFftSize = 1024;
constexpr double kCommonDelayS = 16.0 / kRate + kHeadRadiusM / kHeadSpeedOfSoundMS;
// Brown & Duda's fit to the rigid sphere: the shadow's zero moves with the angle theta to
// the ear, alpha(theta) = (1 + a_min/2) + (1 - a_min/2) cos(theta / theta_min * 180 deg).
constexpr double kAlphaMin = 0.1;
constexpr double kThetaMinRad = 150.0 * kPi / 180.0;

const Eigen::Vector3d kLeftEar(0.0, 1.0, 0.0);
const Eigen::Vector3d kRightEar(0.0, -1.0, 0.0);

// Angle between the source direction and an ear's axis, 0 when the source faces the ear.
double angleToEar(const Eigen::Vector3d& direction, const Eigen::Vector3d& ear) {
  return std::acos(std::clamp(direction.normalized().dot(ear), -1.0, 1.0));
}

// Woodworth-Schlosberg delay to an ear relative to the head centre (Brown & Duda eq. 3):
// a plane wave reaches a lit ear early by a cos(theta) / c, and a shadowed one late by the
// path around the sphere, a (theta - pi/2) / c.
double earDelayS(double theta) {
  const double a_over_c = kHeadRadiusM / kHeadSpeedOfSoundMS;
  return theta < 0.5 * kPi ? -a_over_c * std::cos(theta) : a_over_c * (theta - 0.5 * kPi);
}

std::vector<float> earImpulseResponse(double theta) {
  const double omega_0 = kHeadSpeedOfSoundMS / kHeadRadiusM;
  const double alpha = (1.0 + 0.5 * kAlphaMin) + (1.0 - 0.5 * kAlphaMin) * std::cos(theta / kThetaMinRad * kPi);
  const double delay_s = kCommonDelayS + earDelayS(theta);
  core::RealFft fft(kSynthesisFftSize);
  std::vector<std::complex<float>> spectrum(fft.spectrumSize());
  for (std::size_t k = 0; k < spectrum.size(); ++k) {
    const double f = kRate * static_cast<double>(k) / static_cast<double>(kSynthesisFftSize);
    const double omega = 2.0 * kPi * f;
    const std::complex<double> shadow = (1.0 + std::complex<double>(0.0, alpha * omega / (2.0 * omega_0))) /
                                        (1.0 + std::complex<double>(0.0, omega / (2.0 * omega_0)));
    // A raised-cosine roll-off from 18 kHz to Nyquist keeps the band-limited delay's
    // sinc tails short; the bands the tests look at (up to 16 kHz) are untouched.
    const double rolloff = f <= 18000.0 ? 1.0 : 0.5 * (1.0 + std::cos(kPi * (f - 18000.0) / (0.5 * kRate - 18000.0)));
    spectrum[k] = std::complex<float>(rolloff * shadow * std::polar(1.0, -omega * delay_s));
  }
  std::vector<float> impulse_response = fft.inverse(spectrum);
  impulse_response.resize(kSphericalHeadHrirLength);
  return impulse_response;
}

}  // namespace

core::Hrir sphericalHeadHrir(const Eigen::Vector3d& direction) {
  return {earImpulseResponse(angleToEar(direction, kLeftEar)), earImpulseResponse(angleToEar(direction, kRightEar))};
}

double sphericalHeadItdS(const Eigen::Vector3d& direction) {
  return earDelayS(angleToEar(direction, kRightEar)) - earDelayS(angleToEar(direction, kLeftEar));
}

core::HrtfSet sphericalHeadHrtfSet(std::size_t direction_count) {
  std::vector<Eigen::Vector3d> directions = core::fibonacciLayout(direction_count);
  std::vector<core::Hrir> hrirs;
  hrirs.reserve(directions.size());
  for (const auto& direction : directions) hrirs.push_back(sphericalHeadHrir(direction));
  return core::HrtfSet(kRate, std::move(directions), std::move(hrirs), "spherical head (Brown & Duda 1998)");
}

const core::BinauralDecoder& sphericalHeadDecoder(int order) {
  static std::map<int, core::BinauralDecoder> decoders;
  auto it = decoders.find(order);
  if (it == decoders.end()) it = decoders.emplace(order, core::makeBinauralDecoder(sphericalHeadHrtfSet(), order)).first;
  return it->second;
}

}  // namespace room_reverb::test
