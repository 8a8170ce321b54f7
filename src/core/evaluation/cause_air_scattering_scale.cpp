// The one-parameter hypotheses: air humidity, global scattering, room scale.
#include <sstream>

#include "cause_fitting.h"

namespace room_reverb::core {

std::optional<FittedCause> fitAirAbsorption(const FitContext& context, std::string& /*why*/) {
  // The model's temperature is kept (or 20 degC when it has no air): temperature and
  // humidity trade off almost one for one in ISO 9613-1 above 2 kHz, so only one of them
  // can be fitted from decay times, and humidity is the one that is rarely known.
  AirConditions air = context.evaluator.room().airWith(context.accepted);
  const double temperature = air.enabled ? air.temperature_c : 20.0;
  const auto make = [&](double humidity) {
    ModelExtension e;
    e.air = AirConditions{true, temperature, humidity, air.pressure_kpa};
    return e;
  };
  const ScalarFit fit = fitScalar([&](double h) { return evaluateWith(context, make(h)); }, 10.0, 90.0, 5, 4);
  FittedCause cause;
  cause.cause = "air_absorption";
  cause.extension = make(fit.value);
  cause.parameters.values = {{"temperature_c", temperature}, {"humidity_percent", fit.value}};
  cause.evaluation = fit.evaluation;
  return cause;
}

std::optional<FittedCause> fitScattering(const FitContext& context, std::string& /*why*/) {
  const auto make = [](double s) {
    ModelExtension e;
    e.global_scattering = s;
    return e;
  };
  const ScalarFit fit = fitScalar([&](double s) { return evaluateWith(context, make(s)); }, 0.0, 1.0, 5, 3);
  FittedCause cause;
  cause.cause = "scattering";
  cause.extension = make(fit.value);
  cause.parameters.values = {{"scattering", fit.value}};
  cause.evaluation = fit.evaluation;
  return cause;
}

std::optional<FittedCause> fitGeometryScale(const FitContext& context, std::string& /*why*/) {
  // Scaled about the room's origin (a floor corner for room models), as a visual route's
  // wrong baseline or a wrong unit would scale it; the measured positions stay put.
  const auto make = [](double k) {
    ModelExtension e;
    e.geometry_scale = k;
    return e;
  };
  const ScalarFit fit = fitScalar([&](double k) { return evaluateWith(context, make(k)); }, 0.85, 1.15, 7, 4);
  FittedCause cause;
  cause.cause = "geometry_scale";
  cause.extension = make(fit.value);
  cause.parameters.values = {{"scale", fit.value}};
  cause.evaluation = fit.evaluation;
  return cause;
}

}  // namespace room_reverb::core
