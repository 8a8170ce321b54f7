#include "room_reverb/acoustics/room_modes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

// An octave-band quantity at `frequency_hz`, linear in log frequency between the band
// centres (1 kHz * 2^(k - 4), k = 0 .. 8), held flat beyond the outer centres.
double atFrequency(const OctaveBandValues& values, double frequency_hz) {
  const double position = std::log2(std::max(frequency_hz, 1.0) / 1000.0) + 4.0;
  if (position <= 0.0) return values.front();
  if (position >= kOctaveBandCount - 1) return values.back();
  const auto k = static_cast<std::size_t>(position);
  const double w = position - static_cast<double>(k);
  return (1.0 - w) * values[k] + w * values[k + 1];
}

// The energy decay rate of one mode (header: Kuttruff's eps weights).
double energyDecayPerS(const ModalRoom& room, const std::array<int, 3>& n, double frequency_hz) {
  double weighted_area = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double eps = n[static_cast<std::size_t>(axis)] > 0 ? 2.0 : 1.0;
    weighted_area += eps * atFrequency(room.absorption_area_m2[static_cast<std::size_t>(axis)], frequency_hz);
  }
  return room.speed_of_sound_m_s * weighted_area / (8.0 * room.volumeM3());
}

void requireInBox(const ModalRoom& room, const Eigen::Vector3d& p, const char* what) {
  const Eigen::Vector3d local = p - room.origin_m;
  if (!p.allFinite() || (local.array() < 0.0).any() || (local.array() > room.size_m.array()).any()) {
    throw InputError(std::string("room modes: the ") + what + " is outside the room's box");
  }
}

}  // namespace

ModalRoom modalRoomFromScene(const AcousticScene& scene, double speed_of_sound_m_s) {
  const TriangleMesh& mesh = scene.mesh();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  ModalRoom room;
  room.origin_m = lo;
  room.size_m = hi - lo;
  room.speed_of_sound_m_s = speed_of_sound_m_s;
  if (!room.size_m.allFinite() || room.size_m.minCoeff() <= 0.0) throw InputError("room modes: the room's box is flat");
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const Eigen::Vector3d n = mesh.normal(t);
    const double area = mesh.area(t);
    const OctaveBandValues& alpha = scene.material(t).absorption;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      for (std::size_t b = 0; b < alpha.size(); ++b) {
        room.absorption_area_m2[axis][b] += n[static_cast<Eigen::Index>(axis)] * n[static_cast<Eigen::Index>(axis)] * area *
                                            -std::log(1.0 - std::min(alpha[b], 0.999));
      }
    }
  }
  return room;
}

double schroederFrequencyHz(double t60_s, double volume_m3) {
  if (!(t60_s > 0.0) || !(volume_m3 > 0.0)) throw InputError("Schroeder frequency: T60 and volume must be positive");
  return 2000.0 * std::sqrt(t60_s / volume_m3);
}

std::vector<RoomMode> roomModes(const ModalRoom& room, double max_frequency_hz, double damping_scale) {
  if (!(max_frequency_hz > 0.0) || !(damping_scale > 0.0) || !std::isfinite(max_frequency_hz)) {
    throw InputError("room modes: the highest frequency and the damping scale must be positive");
  }
  const double c = room.speed_of_sound_m_s;
  std::array<int, 3> most{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    most[axis] = static_cast<int>(std::floor(2.0 * room.size_m[static_cast<Eigen::Index>(axis)] * max_frequency_hz / c));
  }
  std::vector<RoomMode> modes;
  for (int nx = 0; nx <= most[0]; ++nx) {
    for (int ny = 0; ny <= most[1]; ++ny) {
      for (int nz = 0; nz <= most[2]; ++nz) {
        if (nx == 0 && ny == 0 && nz == 0) continue;  // uniform pressure: no oscillation
        const double fx = nx / room.size_m.x(), fy = ny / room.size_m.y(), fz = nz / room.size_m.z();
        const double f = 0.5 * c * std::sqrt(fx * fx + fy * fy + fz * fz);
        if (f > max_frequency_hz) continue;
        RoomMode mode;
        mode.index = {nx, ny, nz};
        mode.frequency_hz = f;
        mode.energy_decay_per_s = damping_scale * energyDecayPerS(room, mode.index, f);
        modes.push_back(mode);
      }
    }
  }
  std::sort(modes.begin(), modes.end(), [](const RoomMode& a, const RoomMode& b) { return a.frequency_hz < b.frequency_hz; });
  return modes;
}

AudioBuffer synthesizeRoomModes(const ModalRoom& room, const Eigen::Vector3d& source, const Eigen::Vector3d& receiver,
                                const ModalSynthesisOptions& options) {
  if (options.ambisonic_order < 0 || options.ambisonic_order > 1) {
    throw InputError("room modes: only omni and first-order ambisonics are synthesised");
  }
  if (!(options.sample_rate_hz > 0.0) || options.frames == 0) {
    throw InputError("room modes: the sample rate and the length must be positive");
  }
  if (!(options.max_frequency_hz < 0.5 * options.sample_rate_hz)) {
    throw InputError("room modes: the highest mode must lie below the Nyquist frequency");
  }
  requireInBox(room, source, "source");
  requireInBox(room, receiver, "receiver");
  const Eigen::Vector3d s = source - room.origin_m, r = receiver - room.origin_m;
  const double c = room.speed_of_sound_m_s, dt = 1.0 / options.sample_rate_hz;
  const std::size_t channels = options.ambisonic_order == 0 ? 1 : 4;
  std::vector<std::vector<double>> out(channels, std::vector<double>(options.frames, 0.0));

  for (const RoomMode& mode : roomModes(room, options.max_frequency_hz, options.damping_scale)) {
    Eigen::Vector3d k, cos_s, cos_r, sin_r;
    for (Eigen::Index i = 0; i < 3; ++i) {
      k[i] = mode.index[static_cast<std::size_t>(i)] * kPi / room.size_m[i];
      cos_s[i] = std::cos(k[i] * s[i]);
      cos_r[i] = std::cos(k[i] * r[i]);
      sin_r[i] = std::sin(k[i] * r[i]);
    }
    const double psi_s = cos_s.prod(), psi_r = cos_r.prod();
    // N_n: 1/2 for each axis the mode varies along.
    double norm = 1.0;
    for (int n : mode.index) norm *= n > 0 ? 0.5 : 1.0;
    const double w = 2.0 * kPi * mode.frequency_hz, delta = 0.5 * mode.energy_decay_per_s;
    if (delta >= w) continue;  // overdamped: no oscillation left to model
    const double wd = std::sqrt(w * w - delta * delta);
    // dt: a sampled unit impulse stands for dt times the continuous one.
    const double amplitude = 4.0 * kPi * c * c * dt / (room.volumeM3() * norm) * psi_s / w;
    // Gradient of psi_n at the receiver over k_n: the mode's share of each direction.
    std::array<double, 4> gain{amplitude * psi_r, 0.0, 0.0, 0.0};
    if (channels == 4) {
      const double kn = w / c;
      Eigen::Vector3d grad;
      grad.x() = -k.x() * sin_r.x() * cos_r.y() * cos_r.z();
      grad.y() = -k.y() * cos_r.x() * sin_r.y() * cos_r.z();
      grad.z() = -k.z() * cos_r.x() * cos_r.y() * sin_r.z();
      // c * integral of exp(-delta t) sin(w t) / w dt = -exp(-delta t) cos(w t) c / w^2.
      gain[1] = -amplitude * grad.y() / kn;  // ACN 1: Y
      gain[2] = -amplitude * grad.z() / kn;  // ACN 2: Z
      gain[3] = -amplitude * grad.x() / kn;  // ACN 3: X
    }
    // Damped oscillators by the two-term recurrence y[n] = 2 rho cos(wd dt) y[n-1] -
    // rho^2 y[n-2], run until the envelope is 120 dB down.
    const double rho = std::exp(-delta * dt), a1 = 2.0 * rho * std::cos(wd * dt), a2 = rho * rho;
    const auto length = std::min<std::size_t>(options.frames, static_cast<std::size_t>(std::ceil(13.8 / std::max(delta, 1e-3) / dt)) + 2);
    double sin_prev = 0.0, sin_now = rho * std::sin(wd * dt);  // exp(-delta t) sin(wd t) at n = 0, 1
    double cos_prev = 1.0, cos_now = rho * std::cos(wd * dt);
    for (std::size_t ch = 1; ch < channels; ++ch) out[ch][0] += gain[ch] * cos_prev;
    for (std::size_t n = 1; n < length; ++n) {
      out[0][n] += gain[0] * sin_now;
      for (std::size_t ch = 1; ch < channels; ++ch) out[ch][n] += gain[ch] * cos_now;
      const double sin_next = a1 * sin_now - a2 * sin_prev, cos_next = a1 * cos_now - a2 * cos_prev;
      sin_prev = sin_now;
      sin_now = sin_next;
      cos_prev = cos_now;
      cos_now = cos_next;
    }
  }
  AudioBuffer buffer;
  buffer.sample_rate_hz = options.sample_rate_hz;
  for (const std::vector<double>& channel : out) buffer.channels.emplace_back(channel.begin(), channel.end());
  return buffer;
}

}  // namespace room_reverb::core
