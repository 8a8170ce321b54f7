#pragma once
// The low band of a simulated response from the wave solver (fdtd_solver.h) instead of
// the geometric one, joined to the geometric response at a crossover.
//
// The walls' admittance depends on frequency through the materials' octave absorption:
// the solver runs once per octave band that reaches below the crossover's top, each run
// with that octave's admittances (boundary_admittance.h), and each run contributes its
// own octave (the zero-phase, amplitude-complementary octave bank, so the bands add up to
// the signal again); the octaves above the last run take the last run's. In third octaves
// (WaveLowBandOptions::bands) the same per third, three times the runs. The sum, W and
// the first-order X, Y, Z, is resampled to 48 kHz and joined to the geometric response
// with the zero-phase crossover of audio/crossover.h (half amplitude at the crossover,
// one octave wide). Channels above first order keep the geometric response.
//
// The grid has `cells_per_wavelength` cells per wavelength at the crossover frequency;
// at the top of the crossover's width (half an octave above) the wave part weighs nothing
// and its waves along the grid's axes are about 2 % slow there. Air absorption is left
// out below the crossover (under 0.002 dB/m at 500 Hz).
#include <Eigen/Core>
#include <functional>
#include <string>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

enum class LowBandMethod { kGeometric, kWave };
LowBandMethod parseLowBandMethod(const std::string& name);  // "geometric" | "wave"
std::string toString(LowBandMethod method);

struct WaveLowBandOptions {
  double crossover_hz = 500.0;
  double cells_per_wavelength = 10.0;  // at the crossover frequency
  int threads = 0;                     // 0: all hardware threads
  // Third octaves: one run per third that reaches below the crossover's top, each with its
  // third's admittances (the materials' third-octave absorption where they have it), each
  // contributing its own third (SimulationSettings::bands sets it).
  BandResolution bands = BandResolution::kOctave;
};

// Told a line after each solver run (its octave, how many runs there are, its time).
using WaveProgress = std::function<void(const std::string& line)>;

struct WaveLowBandStats {
  bool used = false;
  double crossover_hz = 0.0;
  double grid_spacing_m = 0.0;
  std::size_t grid_cells = 0;
  std::size_t solver_runs = 0;
  // The wave response's energy over the geometric one's in the octave band at the
  // crossover, dB: how well the two agree where they are joined.
  double overlap_level_db = 0.0;
  double seconds = 0.0;  // wall time of the solver runs
};

struct WaveLowBand {
  AudioBuffer response;  // 48 kHz, W X Y Z (ACN/SN3D), the image sources' gain convention
  WaveLowBandStats stats;
};

// The wave solver's response from `source` to `listener`, `duration_s` long. Throws
// InputError for a crossover outside [63, 2000] Hz, fewer than 4 cells per wavelength, a
// source or listener too near a surface for the grid, or a grid of more than 2^31 cells.
WaveLowBand simulateWaveLowBand(const AcousticScene& scene, const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                                double speed_of_sound_m_s, double duration_s, const WaveLowBandOptions& options,
                                const WaveProgress& progress = {});

// `geometric` with its channels 0-3 below the crossover replaced by `wave`'s; the stats'
// overlap level is filled in.
AudioBuffer joinWaveLowBand(const WaveLowBand& wave, const AudioBuffer& geometric, WaveLowBandStats& stats);

}  // namespace room_reverb::core
