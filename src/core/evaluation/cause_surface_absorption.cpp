// surface_absorption: absorption per octave band fitted to the fit evidence. The target is
// one surface (or material), or every surface at once (`all_surfaces`: one absorption per
// band added to each, for a model whose materials all absorb too little or too much, as a
// visual route's library guesses may). Every target is probed once, its absorption moved by
// kProbe in every band at the base seed, so that the slope of every fit term (decay times,
// EDT, clarity, DRR, the early windows) is measured rather than taken from Sabine's formula
// (absorption_step.h says why); the targets whose probe predicts the largest fall of the
// fit error get Gauss-Newton steps, and the one whose fit leaves the smallest fit error is
// the cause's target.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "cause_fitting.h"
#include "room_reverb/evaluation/absorption_step.h"
#include "room_reverb/evaluation/material_match.h"

namespace room_reverb::core {
namespace {

constexpr double kProbe = 0.1;              // largest absorption added (or taken) to measure the slopes
constexpr double kProbeAreaFraction = 0.2;  // the probe's share of the room's absorption area
constexpr std::size_t kSteppedTargets = 4;  // targets that get steps, by the fall their probe predicts
constexpr int kSteps = 2;                   // Gauss-Newton steps per stepped target
constexpr double kMinTargetAreaM2 = 1.0;  // smaller objects cannot move a decay time
constexpr const char* kAllSurfaces = "all_surfaces";  // the pseudo-target of one change on every surface

OctaveBandValues currentAbsorption(const FitContext& context, const std::string& target) {
  const auto it = context.accepted.absorption.find(target);
  return it != context.accepted.absorption.end() ? it->second : context.evaluator.room().absorptionOf(target);
}

// The per-band changes where a step measured a slope (absorption_step.h), interpolated linearly
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

OctaveBandValues clampedSum(const OctaveBandValues& alpha, const OctaveBandValues& change) {
  OctaveBandValues next{};
  for (std::size_t b = 0; b < next.size(); ++b) next[b] = std::clamp(alpha[b] + change[b], 0.01, 0.99);
  return next;
}

// One target: the surfaces whose absorption changes, their absorption before the fit and
// (for the chosen target) after it.
struct TargetFit {
  std::string name;
  std::vector<std::string> surfaces;
  std::map<std::string, OctaveBandValues> before, alpha;
};

TargetFit startFit(const FitContext& context, const std::string& name, std::vector<std::string> surfaces) {
  TargetFit fit;
  fit.name = name;
  fit.surfaces = std::move(surfaces);
  for (const std::string& s : fit.surfaces) fit.before[s] = currentAbsorption(context, s);
  return fit;
}

// What `alpha` adds to the target, as applied: the change in absorption area over the
// target's area (clamping makes it differ from the offset asked for).
OctaveBandValues appliedOffset(const FitContext& context, const TargetFit& fit,
                               const std::map<std::string, OctaveBandValues>& alpha) {
  OctaveBandValues applied{};
  double total_area = 0.0;
  for (const std::string& s : fit.surfaces) {
    const double area = context.evaluator.room().areaOf(s);
    for (std::size_t b = 0; b < applied.size(); ++b) applied[b] += area * (alpha.at(s)[b] - fit.before.at(s)[b]);
    total_area += area;
  }
  for (double& a : applied) a /= total_area;
  return applied;
}

// The target's absorption with `offset` added, clamped per surface to 0.01-0.99.
std::map<std::string, OctaveBandValues> withOffset(const TargetFit& fit, const OctaveBandValues& offset) {
  std::map<std::string, OctaveBandValues> alpha;
  for (const std::string& s : fit.surfaces) alpha[s] = clampedSum(fit.before.at(s), offset);
  return alpha;
}

// The equivalent absorption area per band of the current model (m^2).
OctaveBandValues absorptionArea(const FitContext& context) {
  OctaveBandValues area{};
  const RoomUnderTest& room = context.evaluator.room();
  for (const std::string& target : room.absorptionTargets()) {
    const OctaveBandValues alpha = currentAbsorption(context, target);
    for (std::size_t b = 0; b < area.size(); ++b) area[b] += room.areaOf(target) * alpha[b];
  }
  return area;
}

// The probe adds kProbeAreaFraction of the room's absorption area per band, at most kProbe
// of absorption: in a room that absorbs little, 0.1 on every surface would triple its
// absorption and the probe's secant would say little about the slope where the fit starts
// (BRAS CR2's naive model, session 17). It moves each band towards the middle of the
// range, so that clamping cannot swallow it: up where the target's (area-weighted)
// absorption is below 0.5, down above.
OctaveBandValues probeOffset(const FitContext& context, const TargetFit& fit, const OctaveBandValues& room_area) {
  OctaveBandValues mean{}, probe{};
  double total_area = 0.0;
  for (const std::string& s : fit.surfaces) {
    const double area = context.evaluator.room().areaOf(s);
    for (std::size_t b = 0; b < mean.size(); ++b) mean[b] += area * fit.before.at(s)[b];
    total_area += area;
  }
  for (std::size_t b = 0; b < probe.size(); ++b) {
    const double size = std::min(kProbe, kProbeAreaFraction * room_area[b] / total_area);
    probe[b] = mean[b] / total_area < 0.5 ? size : -size;
  }
  return probe;
}

CauseParameters parametersOf(const FitContext& context, const TargetFit& fit) {
  CauseParameters parameters;
  if (fit.surfaces.size() == 1) {
    const OctaveBandValues& alpha = fit.alpha.at(fit.surfaces.front());
    parameters.bands["absorption"] = std::vector<double>(alpha.begin(), alpha.end());
    const OctaveBandValues& before = fit.before.at(fit.surfaces.front());
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
    // What was added, as applied (clamped to 0.01-0.99 per surface).
    const OctaveBandValues applied = appliedOffset(context, fit, fit.alpha);
    const std::vector<double> added(applied.begin(), applied.end());
    parameters.bands["absorption_added"] = added;
  }
  return parameters;
}

}  // namespace

std::optional<FittedCause> fitSurfaceAbsorption(const FitContext& context, std::string& why) {
  const RoomUnderTest& room = context.evaluator.room();
  std::vector<TargetFit> candidates;
  std::vector<std::string> all;
  for (const std::string& target : room.absorptionTargets()) {
    all.push_back(target);
    if (room.areaOf(target) >= kMinTargetAreaM2) candidates.push_back(startFit(context, target, {target}));
  }
  if (candidates.size() > 1) candidates.push_back(startFit(context, kAllSurfaces, all));
  if (candidates.empty()) {
    why = "no surface large enough to move a decay time";
    return std::nullopt;
  }

  // The probes: one simulation per target, and the step each predicts.
  struct Probe {
    TargetFit* fit;
    OffsetEvaluation at;
    Evaluation evaluation;
    AbsorptionStep step;
  };
  std::vector<Probe> probes;
  const OffsetEvaluation current{{}, &context.current};
  const OctaveBandValues room_area = absorptionArea(context);
  for (TargetFit& fit : candidates) {
    Probe p{&fit, {}, {}, {}};
    ModelExtension extension;
    extension.absorption = withOffset(fit, probeOffset(context, fit, room_area));
    p.at.offset = appliedOffset(context, fit, extension.absorption);
    p.evaluation = evaluateWith(context, extension);
    if (!p.evaluation.valid) continue;
    probes.push_back(std::move(p));
  }
  for (Probe& p : probes) p.step = gaussNewtonAbsorptionStep(current, {{p.at.offset, &p.evaluation}});
  std::sort(probes.begin(), probes.end(),
            [](const Probe& a, const Probe& b) { return a.step.predicted_reduction > b.step.predicted_reduction; });
  if (probes.size() > kSteppedTargets) probes.resize(kSteppedTargets);
  for (Probe& p : probes) p.at.evaluation = &p.evaluation;  // where each probe now lies

  std::optional<FittedCause> best;
  std::optional<TargetFit> best_fit;  // its parameters are described once, after the search
  double best_error = std::numeric_limits<double>::infinity();
  for (Probe& p : probes) {
    std::vector<OffsetEvaluation> known{current, p.at};
    std::vector<Evaluation> stepped;  // kept alive for `known`
    stepped.reserve(kSteps);
    OffsetEvaluation at = current;
    AbsorptionStep step = p.step;
    for (int k = 0; k < kSteps; ++k) {
      if (std::none_of(step.change.begin(), step.change.end(), [](const auto& c) { return c.has_value(); })) break;
      const OctaveBandValues change = interpolatedChange(step.change);
      OctaveBandValues asked{};
      for (std::size_t b = 0; b < asked.size(); ++b) asked[b] = at.offset[b] + change[b];
      ModelExtension extension;
      OffsetEvaluation next;
      extension.absorption = withOffset(*p.fit, asked);
      next.offset = appliedOffset(context, *p.fit, extension.absorption);
      stepped.push_back(evaluateWith(context, extension));
      if (!stepped.back().valid) break;
      next.evaluation = &stepped.back();
      if (stepped.back().fit_error_jnd < best_error) {
        best_error = stepped.back().fit_error_jnd;
        FittedCause cause;
        cause.cause = "surface_absorption";
        cause.target = p.fit->name;
        cause.extension = extension;
        cause.evaluation = stepped.back();
        best = std::move(cause);
        best_fit = *p.fit;
        best_fit->alpha = extension.absorption;
      }
      step = gaussNewtonAbsorptionStep(next, known);
      known.push_back(next);
      at = next;
    }
  }
  if (!best) {
    why = "no target's absorption moved the fit evidence measurably";
    return best;
  }
  best->parameters = parametersOf(context, *best_fit);
  return best;
}

}  // namespace room_reverb::core
