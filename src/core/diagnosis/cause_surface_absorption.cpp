// surface_absorption: absorption per octave band fitted to the fit evidence. The target is
// one surface (or material), or every surface at once (`all_surfaces`: one absorption per
// band added to each, for a model whose materials all absorb too little or too much, as a
// visual route's library guesses may). Every target is probed once, its absorption moved in
// every band at the base seed, so that the slope of every fit term (decay times, EDT,
// clarity, DRR, the early windows, the early directions) is measured rather than taken
// from Sabine's formula (absorption_step.h says why); every target then takes Gauss-Newton
// steps (the best few until a step stops gaining), and of the targets whose fits leave the
// least fit error (within noise), the one whose early energy comes from the measured
// directions is the cause's target.
#include <algorithm>
#include <deque>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "cause_fitting.h"
#include "room_reverb/diagnosis/absorption_step.h"
#include "room_reverb/diagnosis/material_match.h"

namespace room_reverb::core {
namespace {

constexpr double kProbe = 0.1;              // largest absorption added (or taken) to measure the slopes
constexpr double kProbeAreaFraction = 0.2;  // the probe's share of the room's absorption area
constexpr std::size_t kSteppedTargets = 4;  // targets that take every step, by their first step's fit error
constexpr int kSteps = 2;                   // Gauss-Newton steps every stepped target takes
constexpr int kMaxSteps = 5;                // ... and at most, while a step still gains
constexpr double kMinStepGainJnd = 0.02;    // least fit-error drop that is a gain (when the noise is smaller)
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
// (BRAS CR2's naive model). It moves each band towards the middle of the
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

  // Every target is probed once (the slopes where the fit starts), then takes one
  // Gauss-Newton step; the kSteppedTargets whose first step left the least fit error take
  // the others. Ranking by the probe's linear prediction instead leaves the planted wall
  // out of the four in 2 of 7 planted rooms.
  struct TargetSearch {
    TargetFit* fit = nullptr;
    std::vector<OffsetEvaluation> known;   // the current model, the probe and the steps
    OffsetEvaluation at;                   // the last step (the current model before any)
    AbsorptionStep step;                   // the next step
    std::optional<ModelExtension> best;    // the step of least fit error
    const Evaluation* best_evaluation = nullptr;
  };
  std::vector<TargetSearch> searches;
  // Every evaluation of the search, in one place that never moves them (a deque keeps its
  // elements where they are as it grows): `known` and `best_evaluation` point into it.
  std::deque<Evaluation> evaluations;
  const OffsetEvaluation current{{}, &context.current};
  const OctaveBandValues room_area = absorptionArea(context);
  // The probes of every target are one batch (evaluateWithEach), as are their first steps:
  // a runner simulates them together.
  std::vector<ModelExtension> probes;
  for (TargetFit& fit : candidates) {
    ModelExtension extension;
    extension.absorption = withOffset(fit, probeOffset(context, fit, room_area));
    probes.push_back(std::move(extension));
  }
  std::vector<Evaluation> probed = evaluateWithEach(context, probes);
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    TargetSearch t;
    t.fit = &candidates[k];
    evaluations.push_back(std::move(probed[k]));
    if (!evaluations.back().valid) continue;
    t.known = {current, {appliedOffset(context, candidates[k], probes[k].absorption), &evaluations.back()}};
    t.at = current;
    t.step = gaussNewtonAbsorptionStep(current, {t.known.back()});
    searches.push_back(std::move(t));
  }
  const auto next_step = [&](const TargetSearch& t) -> std::optional<ModelExtension> {
    if (std::none_of(t.step.change.begin(), t.step.change.end(), [](const auto& c) { return c.has_value(); })) {
      return std::nullopt;
    }
    const OctaveBandValues change = interpolatedChange(t.step.change);
    OctaveBandValues asked{};
    for (std::size_t b = 0; b < asked.size(); ++b) asked[b] = t.at.offset[b] + change[b];
    ModelExtension extension;
    extension.absorption = withOffset(*t.fit, asked);
    return extension;
  };
  const auto record_step = [&](TargetSearch& t, const ModelExtension& extension, Evaluation evaluation) {
    evaluations.push_back(std::move(evaluation));
    if (!evaluations.back().valid) {
      t.step = {};
      return;
    }
    const OffsetEvaluation next{appliedOffset(context, *t.fit, extension.absorption), &evaluations.back()};
    if (!t.best_evaluation || next.evaluation->fit_error_jnd < t.best_evaluation->fit_error_jnd) {
      t.best = extension;
      t.best_evaluation = next.evaluation;
    }
    t.step = gaussNewtonAbsorptionStep(next, t.known);
    t.known.push_back(next);
    t.at = next;
  };
  const auto take_step = [&](TargetSearch& t) {
    if (const std::optional<ModelExtension> extension = next_step(t)) record_step(t, *extension, evaluateWith(context, *extension));
  };
  std::vector<TargetSearch*> stepping;
  std::vector<ModelExtension> steps;
  for (TargetSearch& t : searches) {
    if (std::optional<ModelExtension> extension = next_step(t)) {
      stepping.push_back(&t);
      steps.push_back(std::move(*extension));
    }
  }
  std::vector<Evaluation> stepped = evaluateWithEach(context, steps);
  for (std::size_t k = 0; k < stepping.size(); ++k) record_step(*stepping[k], steps[k], std::move(stepped[k]));
  searches.erase(std::remove_if(searches.begin(), searches.end(), [](const TargetSearch& t) { return !t.best; }),
                 searches.end());
  std::sort(searches.begin(), searches.end(), [](const TargetSearch& a, const TargetSearch& b) {
    return a.best_evaluation->fit_error_jnd < b.best_evaluation->fit_error_jnd;
  });
  // A stepped target steps on while its last step lowered the fit error by more than the
  // noise: from a model far off (BRAS CR2's naive one, with T20 and EDT at the 10 JND cap,
  // which the first step leaves out) two steps leave T20 at 2.7 JND.
  const double least_gain = std::max(kMinStepGainJnd, context.noise_jnd);
  for (std::size_t i = 0; i < searches.size() && i < kSteppedTargets; ++i) {
    for (int k = 1; k < kMaxSteps; ++k) {
      const double before = searches[i].best_evaluation->fit_error_jnd;
      take_step(searches[i]);
      if (k + 1 >= kSteps && before - searches[i].best_evaluation->fit_error_jnd <= least_gain) break;
    }
  }
  if (searches.empty()) {
    why = "no target's absorption moved the fit evidence measurably";
    return std::nullopt;
  }

  // The target. Fitted to the same evidence, targets whose fit errors lie within the
  // evaluation's noise of the least are tied: the decay times, clarity, DRR and early
  // energy (all omni) fix how much absorption is added, not where. What says where is
  // the direction the early energy comes from (the `directions` group of B-format
  // measurements), so it breaks the tie; without it the least fit error wins.
  double least = std::numeric_limits<double>::infinity();
  for (const TargetSearch& t : searches) least = std::min(least, t.best_evaluation->fit_error_jnd);
  const auto directions_error = [](const Evaluation& e) {
    const std::map<std::string, double> groups = groupMeanAbsoluteErrors(e.terms, 0);
    const auto it = groups.find("directions");
    return it == groups.end() ? std::optional<double>{} : std::optional<double>{it->second};
  };
  const TargetSearch* chosen = nullptr;
  std::optional<double> chosen_directions;
  for (const TargetSearch& t : searches) {
    const Evaluation& e = *t.best_evaluation;
    if (e.fit_error_jnd > least + context.noise_jnd) continue;
    const std::optional<double> mine = directions_error(e);
    const bool better = !chosen || (mine && chosen_directions ? *mine < *chosen_directions
                                                              : e.fit_error_jnd < chosen->best_evaluation->fit_error_jnd);
    if (better) {
      chosen = &t;
      chosen_directions = mine;
    }
  }
  std::optional<FittedCause> best = FittedCause{};
  best->cause = "surface_absorption";
  best->target = chosen->fit->name;
  best->extension = *chosen->best;
  best->evaluation = *chosen->best_evaluation;
  TargetFit best_fit = *chosen->fit;
  best_fit.alpha = chosen->best->absorption;
  best->parameters = parametersOf(context, best_fit);
  return best;
}

}  // namespace room_reverb::core
