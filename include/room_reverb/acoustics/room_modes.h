#pragma once
// The low-frequency response of a room as a sum of its modes, for the band where
// geometrical acoustics fails: below the Schroeder frequency a room's response is a few
// resonances whose levels depend on where source and receiver stand and whose decay rates
// depend on which walls each mode touches; rays see neither.
//
// The room is taken as the rectangular box around its surfaces (exact for shoeboxes, an
// approximation for other rooms). Mode (nx, ny, nz) has the shape
//   psi_n(x) = cos(nx pi x / Lx) cos(ny pi y / Ly) cos(nz pi z / Lz)
// and frequency f_n = c/2 sqrt((nx/Lx)^2 + (ny/Ly)^2 + (nz/Lz)^2). Its energy decays at
//   2 delta_n = c / (8 V) * sum over the three wall pairs of eps_i * A_i(f_n),
// with eps_i = 2 when the mode varies along axis i (n_i > 0) and 1 when it does not
// (Kuttruff, Room Acoustics, 5th ed., section 3.5; Morse and Ingard): an oblique mode
// decays at c A / (4 V), the diffuse-field (Sabine) rate, an axial mode more slowly,
// since it barely touches the walls parallel to it. A_i is the absorption area of the
// surfaces facing axis i, with -ln(1 - alpha) for alpha so that an oblique mode decays
// at Eyring's rate, as the ray tracer's diffuse field does.
//
// The impulse response (Green's function of the box; Kuttruff eq. 3.41 in the time
// domain), scaled as the simulator's (room_simulation.h: the direct sound of an omni
// source at 1 m has unit amplitude, 4 pi times the free-field Green's function):
//   p(t) = 4 pi c^2 / V * sum_n psi_n(S) psi_n(R) / N_n * exp(-delta_n t) sin(w_n t) / w_n
// with N_n the mean of psi_n^2 over the box, times the sampling interval (a sampled unit
// impulse is the continuous one times dt). First-order ambisonic channels follow from
// the pressure gradient (u p = c * integral of grad p for a plane wave from u).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

struct ModalRoom {
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();  // the box's lowest corner
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();
  // Per axis (x, y, z): area (m^2) times -ln(1 - alpha) per octave band of the surfaces
  // facing that axis (a tilted surface shared by the squares of its normal's components).
  std::array<OctaveBandValues, 3> absorption_area_m2{};
  double speed_of_sound_m_s = 343.2;
  double volumeM3() const { return size_m.prod(); }
};

// The box around the scene's surfaces and their absorption. InputError for a scene
// whose box is flat.
ModalRoom modalRoomFromScene(const AcousticScene& scene, double speed_of_sound_m_s);

// Schroeder's frequency 2000 sqrt(T60 / V) (Hz; T60 in s, V in m^3): above it, modes
// overlap (about three per half-power bandwidth) and the field is diffuse.
double schroederFrequencyHz(double t60_s, double volume_m3);

struct RoomMode {
  std::array<int, 3> index{};
  double frequency_hz = 0.0;
  double energy_decay_per_s = 0.0;  // 2 delta_n: the mode's energy falls as exp(-2 delta_n t)
};

// Every mode but (0, 0, 0) up to `max_frequency_hz`, by frequency; decay rates multiplied
// by `damping_scale` (the fitted correction of the wall absorption at low frequencies).
std::vector<RoomMode> roomModes(const ModalRoom& room, double max_frequency_hz, double damping_scale = 1.0);

struct ModalSynthesisOptions {
  double sample_rate_hz = 48000.0;
  std::size_t frames = 0;
  int ambisonic_order = 0;  // 0: omni; 1: ACN/SN3D first order (W, Y, Z, X)
  double max_frequency_hz = 400.0;
  double damping_scale = 1.0;
};

// The modal impulse response from `source` to `receiver` (time 0: the source's
// emission). InputError for a point outside the box or invalid options.
AudioBuffer synthesizeRoomModes(const ModalRoom& room, const Eigen::Vector3d& source, const Eigen::Vector3d& receiver,
                                const ModalSynthesisOptions& options);

}  // namespace room_reverb::core
