// surface_absorption: one target's absorption per octave band, fitted to the decay times
// of the fit evidence by Newton steps whose slope comes from Sabine's formula (T ~ V / A:
// a relative decay error e asks for e * A more absorption area); the target is the one
// whose fit leaves the smallest fit error, since decay times alone cannot tell surfaces
// apart but the early profile and the clarity of other positions can.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "cause_fitting.h"

namespace room_reverb::core {
namespace {

constexpr int kNewtonSteps = 2;
constexpr double kMinTargetAreaM2 = 1.0;  // smaller objects cannot move a decay time

OctaveBandValues currentAbsorption(const FitContext& context, const std::string& target) {
  const auto it = context.accepted.absorption.find(target);
  return it != context.accepted.absorption.end() ? it->second : context.evaluator.room().absorptionOf(target);
}

// Sabine's equivalent absorption area per band of the current model.
OctaveBandValues absorptionArea(const FitContext& context) {
  OctaveBandValues area{};
  const RoomUnderTest& room = context.evaluator.room();
  for (const std::string& target : room.absorptionTargets()) {
    const OctaveBandValues alpha = currentAbsorption(context, target);
    for (std::size_t b = 0; b < area.size(); ++b) area[b] += room.areaOf(target) * alpha[b];
  }
  return area;
}

// One Newton step on every band with a decay bias; bands without one (63 Hz, 16 kHz) take
// their neighbour's change.
OctaveBandValues newtonStep(const OctaveBandValues& alpha, const OctaveBandValues& area_total, double target_area,
                            const std::map<double, double>& bias) {
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  std::vector<std::optional<double>> delta(bands.size());
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const auto it = bias.find(bands[b].nominal_hz);
    if (it != bias.end()) delta[b] = area_total[b] * it->second / target_area;
  }
  OctaveBandValues next = alpha;
  for (std::size_t b = 0; b < bands.size(); ++b) {
    std::optional<double> d = delta[b];
    for (std::size_t k = 1; !d && k < bands.size(); ++k) {
      if (b >= k && delta[b - k]) d = delta[b - k];
      else if (b + k < bands.size() && delta[b + k]) d = delta[b + k];
    }
    next[b] = std::clamp(alpha[b] + d.value_or(0.0), 0.01, 0.99);
  }
  return next;
}

}  // namespace

std::optional<FittedCause> fitSurfaceAbsorption(const FitContext& context, std::string& why) {
  const RoomUnderTest& room = context.evaluator.room();
  const OctaveBandValues area0 = absorptionArea(context);
  const std::map<double, double> bias0 = decayBias(context.current);
  if (bias0.empty()) {
    why = "no decay times in the fit evidence";
    return std::nullopt;
  }
  std::optional<FittedCause> best;
  double best_error = std::numeric_limits<double>::infinity();
  for (const std::string& target : room.absorptionTargets()) {
    const double target_area = room.areaOf(target);
    if (target_area < kMinTargetAreaM2) continue;
    OctaveBandValues alpha = currentAbsorption(context, target);
    OctaveBandValues area_total = area0;
    std::map<double, double> bias = bias0;
    for (int step = 0; step < kNewtonSteps; ++step) {
      const OctaveBandValues next = newtonStep(alpha, area_total, target_area, bias);
      for (std::size_t b = 0; b < next.size(); ++b) area_total[b] += target_area * (next[b] - alpha[b]);
      alpha = next;
      ModelExtension extension;
      extension.absorption[target] = alpha;
      Evaluation evaluation = evaluateWith(context, extension);
      if (!evaluation.valid) break;
      bias = decayBias(evaluation);
      if (evaluation.fit_error_jnd < best_error) {
        best_error = evaluation.fit_error_jnd;
        FittedCause cause;
        cause.cause = "surface_absorption";
        cause.target = target;
        cause.extension = extension;
        cause.parameters.bands["absorption"] = std::vector<double>(alpha.begin(), alpha.end());
        const OctaveBandValues before = currentAbsorption(context, target);
        cause.parameters.bands["absorption_before"] = std::vector<double>(before.begin(), before.end());
        cause.evaluation = std::move(evaluation);
        best = std::move(cause);
      }
    }
  }
  if (!best) why = "no surface large enough to move a decay time";
  return best;
}

}  // namespace room_reverb::core
