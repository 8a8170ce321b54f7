// surface_absorption: absorption per octave band fitted to the decay times of the fit
// evidence by Newton steps whose slope comes from Sabine's formula (T ~ V / A: a relative
// decay error e asks for e * A more absorption area). The target is one surface (or
// material), or every surface at once (`all_surfaces`: one absorption per band added to
// each, for a model whose materials all absorb too little or too much, as a visual route's
// library guesses may). Decay times alone cannot tell targets apart, but the early profile
// and clarity of other positions can: the target is the one whose fit leaves the smallest
// fit error.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "cause_fitting.h"
#include "room_reverb/evaluation/material_match.h"

namespace room_reverb::core {
namespace {

constexpr int kNewtonSteps = 2;
constexpr double kMinTargetAreaM2 = 1.0;  // smaller objects cannot move a decay time
constexpr const char* kAllSurfaces = "all_surfaces";  // the pseudo-target of one change on every surface

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

// The per-band changes where the fit evidence has a decay bias, interpolated linearly
// over the octave index between them and held constant beyond them (63 Hz, 16 kHz, and
// the held-out bands of a band split, model_evaluation.h): a material's absorption is
// smooth in frequency, so a held-out band gets what its neighbours say, not a free value.
OctaveBandValues interpolatedChange(const std::vector<std::optional<double>>& known) {
  OctaveBandValues change{};
  const int n = static_cast<int>(known.size());
  for (int b = 0; b < n; ++b) {
    int lo = b, hi = b;
    while (lo >= 0 && !known[static_cast<std::size_t>(lo)]) --lo;
    while (hi < n && !known[static_cast<std::size_t>(hi)]) ++hi;
    if (lo >= 0 && hi < n && hi != lo) {
      const double w = static_cast<double>(b - lo) / static_cast<double>(hi - lo);
      change[static_cast<std::size_t>(b)] = (1.0 - w) * *known[static_cast<std::size_t>(lo)] + w * *known[static_cast<std::size_t>(hi)];
    } else if (lo >= 0) {
      change[static_cast<std::size_t>(b)] = *known[static_cast<std::size_t>(lo)];
    } else if (hi < n) {
      change[static_cast<std::size_t>(b)] = *known[static_cast<std::size_t>(hi)];
    }
  }
  return change;
}

// One Newton step: the absorption each band of the target must add, as a coefficient over
// the target's area.
OctaveBandValues newtonChange(const OctaveBandValues& area_total, double target_area, const std::map<double, double>& bias) {
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  std::vector<std::optional<double>> delta(bands.size());
  for (std::size_t b = 0; b < bands.size(); ++b) {
    const auto it = bias.find(bands[b].nominal_hz);
    if (it != bias.end()) delta[b] = area_total[b] * it->second / target_area;
  }
  return interpolatedChange(delta);
}

OctaveBandValues clampedSum(const OctaveBandValues& alpha, const OctaveBandValues& change) {
  OctaveBandValues next{};
  for (std::size_t b = 0; b < next.size(); ++b) next[b] = std::clamp(alpha[b] + change[b], 0.01, 0.99);
  return next;
}

// What one target's fit changes: its absorptions, the model's absorption area, and the
// cause's parameters.
struct TargetFit {
  std::string name;
  std::vector<std::string> surfaces;  // the targets whose absorption changes
  double area = 0.0;
  std::map<std::string, OctaveBandValues> alpha;
};

TargetFit startFit(const FitContext& context, const std::string& name, std::vector<std::string> surfaces) {
  TargetFit fit;
  fit.name = name;
  fit.surfaces = std::move(surfaces);
  for (const std::string& s : fit.surfaces) {
    fit.area += context.evaluator.room().areaOf(s);
    fit.alpha[s] = currentAbsorption(context, s);
  }
  return fit;
}

// Applies one Newton step, keeping the model's absorption area up to date.
void step(const FitContext& context, TargetFit& fit, OctaveBandValues& area_total, const std::map<double, double>& bias) {
  const OctaveBandValues change = newtonChange(area_total, fit.area, bias);
  for (const std::string& s : fit.surfaces) {
    const OctaveBandValues next = clampedSum(fit.alpha[s], change);
    const double area = context.evaluator.room().areaOf(s);
    for (std::size_t b = 0; b < next.size(); ++b) area_total[b] += area * (next[b] - fit.alpha[s][b]);
    fit.alpha[s] = next;
  }
}

CauseParameters parametersOf(const FitContext& context, const TargetFit& fit) {
  CauseParameters parameters;
  if (fit.surfaces.size() == 1) {
    const OctaveBandValues& alpha = fit.alpha.at(fit.surfaces.front());
    parameters.bands["absorption"] = std::vector<double>(alpha.begin(), alpha.end());
    const OctaveBandValues before = currentAbsorption(context, fit.surfaces.front());
    parameters.bands["absorption_before"] = std::vector<double>(before.begin(), before.end());
    // What the surface is, by what it absorbs: the report names the material and flags a
    // fit that absorbs like nothing in the library (material_match.h).
    const MaterialMatch match = nearestMaterial(alpha, context.evaluator.room().library());
    if (!match.material.empty()) {
      parameters.text["nearest_material"] = match.material;
      parameters.values["nearest_material_difference"] = match.max_difference;
      parameters.values["nearest_material_worst_band_hz"] = match.worst_band_hz;
    }
  } else {
    // What was added, as applied (clamped to 0.01-0.99 per surface): the change in
    // absorption area over the area of all the surfaces.
    std::vector<double> added(kOctaveBandCount, 0.0);
    for (const std::string& s : fit.surfaces) {
      const OctaveBandValues before = currentAbsorption(context, s);
      const double area = context.evaluator.room().areaOf(s);
      for (std::size_t b = 0; b < added.size(); ++b) added[b] += area * (fit.alpha.at(s)[b] - before[b]) / fit.area;
    }
    parameters.bands["absorption_added"] = added;
  }
  return parameters;
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
  std::vector<TargetFit> candidates;
  std::vector<std::string> all;
  for (const std::string& target : room.absorptionTargets()) {
    all.push_back(target);
    if (room.areaOf(target) >= kMinTargetAreaM2) candidates.push_back(startFit(context, target, {target}));
  }
  if (candidates.size() > 1) candidates.push_back(startFit(context, kAllSurfaces, all));

  std::optional<FittedCause> best;
  std::optional<TargetFit> best_fit;  // its parameters are described once, after the search
  double best_error = std::numeric_limits<double>::infinity();
  for (TargetFit& fit : candidates) {
    OctaveBandValues area_total = area0;
    std::map<double, double> bias = bias0;
    for (int k = 0; k < kNewtonSteps; ++k) {
      step(context, fit, area_total, bias);
      ModelExtension extension;
      extension.absorption = fit.alpha;
      Evaluation evaluation = evaluateWith(context, extension);
      if (!evaluation.valid) break;
      bias = decayBias(evaluation);
      if (evaluation.fit_error_jnd < best_error) {
        best_error = evaluation.fit_error_jnd;
        FittedCause cause;
        cause.cause = "surface_absorption";
        cause.target = fit.name;
        cause.extension = extension;
        cause.evaluation = std::move(evaluation);
        best = std::move(cause);
        best_fit = fit;
      }
    }
  }
  if (!best) {
    why = "no surface large enough to move a decay time";
    return best;
  }
  best->parameters = parametersOf(context, *best_fit);
  return best;
}

}  // namespace room_reverb::core
