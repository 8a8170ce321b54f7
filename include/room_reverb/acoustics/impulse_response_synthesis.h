#pragma once
// Turning simulation results into a sampled impulse response (ACN/SN3D ambisonics; order
// 0 is omni).
//
// Early part: each image-source path as a band-shaped, fractional-delay tap: a short
// zero-phase FIR whose magnitude interpolates the path's octave gains in energy, delayed
// by the exact (non-integer) number of samples, weighted by the harmonics of its
// direction.
// Late part: a Poisson process of signed impulses whose rate grows as 4 pi c^3 t^2 / V (the
// density of reflections in a room; Kuttruff), filtered into octave (below 1 kHz) and third-octave bands (all
// thirds for a simulation in third octaves) and scaled
// in every histogram bin to the bin's energy (octave energies interpolated across the
// spectrum, so the decay rate changes smoothly with frequency); its direction follows the bin's intensity
// vector, the rest of the energy spread as a diffuse field (SN3D: 1 / (2l + 1) per channel).
#include <array>
#include <cstdint>
#include <vector>

#include "room_reverb/acoustics/energy_histogram.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

// Taps of each path's band-shaping FIR, centred on its arrival: 43 ms at 48 kHz resolves
// the 63 Hz band's gain.
constexpr std::size_t kPathTapLength = 2048;

struct SynthesisOptions {
  double sample_rate_hz = kInternalSampleRateHz;
  double duration_s = 2.0;
  int ambisonic_order = 1;
  double room_volume_m3 = 100.0;     // sets the growth of the reflection density
  double speed_of_sound_m_s = 343.2;
  double max_event_rate_per_s = 12000.0;
  std::uint32_t seed = 1;
};

// Histogram energies are per unit area for 1 J emitted; the output is scaled so that the
// direct sound of an omni source at 1 m has unit energy (4 pi per J/m^2), and each band of the
// late field carries the share of the histogram energy that a white source puts in that band.
AudioBuffer synthesizeImpulseResponse(const std::vector<SpecularPath>& paths, const EnergyHistogram* late,
                                      const SynthesisOptions& options);

// The same in third octaves end to end: paths[k] and late[k] are the simulation of the
// scene's k-th third-octave view (AcousticScene::thirdOctaveBands: band b stands for the
// k-th third of octave b). Every view's image sources are the same arrivals in the same
// order, with that third's gains; each arrival's tap interpolates its 27 third-octave gains
// and the late noise is synthesised in the 27 thirds 50 Hz .. 20 kHz, each scaled to its own
// histogram. late: all null (early part only) or none.
AudioBuffer synthesizeThirdOctaveImpulseResponse(const std::array<const std::vector<SpecularPath>*, 3>& paths,
                                                 const std::array<const EnergyHistogram*, 3>& late,
                                                 const SynthesisOptions& options);

}  // namespace room_reverb::core
