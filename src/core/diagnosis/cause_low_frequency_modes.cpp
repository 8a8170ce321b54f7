// low_frequency_modes: below the Schroeder frequency a room rings in a few modes, whose
// levels depend on where source and receiver stand and whose decays depend on which walls
// each mode touches (axial modes outlast oblique ones); rays know neither. The extension
// synthesises the low band from the modes of the room's box (acoustics/room_modes.h) and
// hands over to the rays at the Schroeder frequency. One parameter is fitted: a factor on
// every mode's damping, since the absorption tables rarely hold at the lowest
// frequencies (and a wall's absorption at normal incidence, which axial modes see, is not
// its random-incidence value). Fitted on a log grid by re-analysing the responses
// already simulated: the modes need no ray tracing.
#include <cmath>

#include "cause_fitting.h"
#include "room_reverb/audio/frequency_bands.h"

namespace room_reverb::core {

std::optional<FittedCause> fitLowFrequencyModes(const FitContext& context, std::string& why) {
  if (context.accepted.modes || context.accepted.wave_low_band) {
    why = context.accepted.modes ? "the low band is already modal" : "the low band is already the wave solver's";
    return std::nullopt;
  }
  const RoomUnderTest& room = context.evaluator.room();
  const AcousticScene scene = room.scene(context.accepted);
  const AirConditions air = room.airWith(context.accepted);
  const double crossover_hz = modalCrossoverHz(scene, air);
  // The modal band must reach into the lowest band scored to change anything.
  const double lowest_scored = standardBands(BandResolution::kOctave)[1].lower_hz;  // 125 Hz octave
  if (crossover_hz * std::sqrt(2.0) < lowest_scored) {
    why = "the Schroeder frequency lies below the bands scored";
    return std::nullopt;
  }
  const ModalRoom modal_room = modalRoomFor(scene, air);
  const auto evaluate = [&](double log_scale) {
    ModelExtension extension;
    extension.modes = LowFrequencyModes{std::exp(log_scale), crossover_hz};
    return reanalyseWith(context, extension, &modal_room);
  };
  // Damping from 0.4 to 2.5 times what the absorption tables give.
  ScalarFit fit = fitScalar(evaluate, std::log(0.4), std::log(2.5), 7, 5);
  if (!fit.evaluation.valid) {
    why = "no valid modal response: " + fit.evaluation.reason;
    return std::nullopt;
  }
  FittedCause cause;
  cause.cause = "low_frequency_modes";
  cause.extension.modes = LowFrequencyModes{std::exp(fit.value), crossover_hz};
  cause.parameters.values = {{"damping_scale", std::exp(fit.value)}, {"crossover_hz", crossover_hz}};
  cause.evaluation = std::move(fit.evaluation);
  return cause;
}

}  // namespace room_reverb::core
