// The causes with nothing to fit: physics the simulation has as switches
// (room_simulation.h). Each is one evaluation of the evidence with the switch on; its gain
// is judged on held-out evidence and at other seeds as every cause's is.
#include "cause_fitting.h"

namespace room_reverb::core {
namespace {

std::optional<FittedCause> switchedOn(const FitContext& context, const char* name, const ModelExtension& extension) {
  FittedCause cause;
  cause.cause = name;
  cause.extension = extension;
  cause.evaluation = evaluateWith(context, extension);
  return cause;
}

}  // namespace

std::optional<FittedCause> fitDiffractionScattering(const FitContext& context, std::string& why) {
  if (context.accepted.diffraction_scattering) {
    why = "the model already has it";
    return std::nullopt;
  }
  ModelExtension extension;
  extension.diffraction_scattering = true;
  return switchedOn(context, "diffraction_scattering", extension);
}

std::optional<FittedCause> fitWaveLowBand(const FitContext& context, std::string& why) {
  if (context.accepted.wave_low_band || context.accepted.modes) {
    why = context.accepted.wave_low_band ? "the model already has it" : "the low band is already modal";
    return std::nullopt;
  }
  ModelExtension extension;
  extension.wave_low_band = true;
  return switchedOn(context, "wave_low_band", extension);
}

std::optional<FittedCause> fitThirdOctaveBands(const FitContext& context, std::string& why) {
  if (context.accepted.third_octave_bands) {
    why = "the model already has it";
    return std::nullopt;
  }
  if (!context.evaluator.room().scene(context.accepted).hasThirdOctaveMaterials()) {
    why = "no material of the model has third-octave coefficients";
    return std::nullopt;
  }
  ModelExtension extension;
  extension.third_octave_bands = true;
  return switchedOn(context, "third_octave_bands", extension);
}

}  // namespace room_reverb::core
