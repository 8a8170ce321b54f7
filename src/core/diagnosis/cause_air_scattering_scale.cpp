// The one-parameter hypotheses: air humidity, global scattering, room scale.
#include "cause_fitting.h"

namespace room_reverb::core {
namespace {

// A cause whose extension is a function of one number, fitted over [lo, hi].
FittedCause scalarCause(const FitContext& context, const std::string& name, const std::string& key,
                        const std::function<ModelExtension(double)>& make, double lo, double hi, int grid,
                        int refinements) {
  const ScalarFit fit = fitScalar([&](double x) { return evaluateWith(context, make(x)); }, lo, hi, grid, refinements,
                                  evaluateEachOf(context, make));
  FittedCause cause;
  cause.cause = name;
  cause.extension = make(fit.value);
  cause.parameters.values[key] = fit.value;
  cause.evaluation = fit.evaluation;
  return cause;
}

}  // namespace

std::optional<FittedCause> fitAirAbsorption(const FitContext& context, std::string& /*why*/) {
  // The model's temperature is kept (or 20 degC when it has no air): temperature and
  // humidity trade off almost one for one in ISO 9613-1 above 2 kHz, so only one of them
  // can be fitted from decay times, and humidity is the one that is rarely known.
  const AirConditions air = context.evaluator.room().airWith(context.accepted);
  const double temperature = air.enabled ? air.temperature_c : 20.0;
  const auto make = [&](double humidity) {
    ModelExtension e;
    e.air = AirConditions{true, temperature, humidity, air.pressure_kpa};
    return e;
  };
  FittedCause cause = scalarCause(context, "air_absorption", "humidity_percent", make, 10.0, 90.0, 5, 4);
  cause.parameters.values["temperature_c"] = temperature;
  return cause;
}

std::optional<FittedCause> fitScattering(const FitContext& context, std::string& /*why*/) {
  const auto make = [](double s) {
    ModelExtension e;
    e.global_scattering = s;
    return e;
  };
  return scalarCause(context, "scattering", "scattering", make, 0.0, 1.0, 5, 6);
}

std::optional<FittedCause> fitGeometryScale(const FitContext& context, std::string& why) {
  // The catalogue's signature of a wrong scale is every reflection arriving late (or early)
  // by one factor. A table of averaged parameters has no arrival times: there the scale
  // shows only through the decay and clarity, where it trades against absorption (Sabine:
  // T ~ V / A grows with the scale). On BRAS CR2's exact mesh, after the air, a scale fit
  // from the table names 0.935 for what is the low-band excess of its ray tracing.
  if (!context.evaluator.evidence().usesRirs()) {
    why = "needs measured RIRs (reflection arrival times)";
    return std::nullopt;
  }
  // Scaled about the room's origin (a floor corner for room models), as a visual route's
  // wrong baseline or a wrong unit would scale it; the measured positions stay put.
  const auto make = [](double k) {
    ModelExtension e;
    e.geometry_scale = k;
    return e;
  };
  return scalarCause(context, "geometry_scale", "scale", make, 0.85, 1.15, 7, 4);
}

}  // namespace room_reverb::core
