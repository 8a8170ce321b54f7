#include "room_reverb/diagnosis/absorption_step.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>

namespace room_reverb::core {
namespace {

using TermKey = std::tuple<int, std::string, double, int>;  // pair, group, band, window

bool isFitTerm(const ErrorTerm& t) { return !t.held_out && t.group != "reflections"; }

std::map<TermKey, double> fitTerms(const Evaluation& e) {
  std::map<TermKey, double> terms;
  for (const ErrorTerm& t : e.terms) {
    if (isFitTerm(t)) terms[{t.pair, t.group, t.band_hz, t.window}] = t.error_jnd;
  }
  return terms;
}

// The evaluation whose offset differs most from `at`'s in band b.
const OffsetEvaluation* farthest(const OffsetEvaluation& at, const std::vector<OffsetEvaluation>& others, std::size_t b) {
  const OffsetEvaluation* best = nullptr;
  for (const OffsetEvaluation& o : others) {
    if (!o.evaluation || !o.evaluation->valid) continue;
    if (!best || std::abs(o.offset[b] - at.offset[b]) > std::abs(best->offset[b] - at.offset[b])) best = &o;
  }
  return best;
}

}  // namespace

AbsorptionStep gaussNewtonAbsorptionStep(const OffsetEvaluation& at, const std::vector<OffsetEvaluation>& others) {
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  AbsorptionStep step;
  step.change.resize(bands.size());
  if (!at.evaluation || !at.evaluation->valid) return step;

  // Each term weighs one over its group's count, as in the fit error (meanAbsoluteError).
  std::map<std::string, int> group_count;
  for (const ErrorTerm& t : at.evaluation->terms) {
    if (isFitTerm(t)) ++group_count[t.group];
  }
  std::map<const Evaluation*, std::map<TermKey, double>> other_terms;
  for (const OffsetEvaluation& o : others) {
    if (o.evaluation && o.evaluation->valid) other_terms[o.evaluation] = fitTerms(*o.evaluation);
  }

  for (std::size_t b = 0; b < bands.size(); ++b) {
    const OffsetEvaluation* other = farthest(at, others, b);
    if (!other) continue;
    const double d = other->offset[b] - at.offset[b];
    if (std::abs(d) < 1e-3) continue;
    const std::map<TermKey, double>& moved = other_terms.at(other->evaluation);
    double num = 0.0, den = 0.0, weights = 0.0;
    for (const ErrorTerm& t : at.evaluation->terms) {
      if (!isFitTerm(t) || std::abs(t.band_hz - bands[b].nominal_hz) > 1e-6) continue;
      const auto it = moved.find({t.pair, t.group, t.band_hz, t.window});
      if (it == moved.end() || std::abs(t.error_jnd) >= kTermCapJnd || std::abs(it->second) >= kTermCapJnd) continue;
      const double w = 1.0 / group_count.at(t.group);
      const double slope = (it->second - t.error_jnd) / d;
      num += w * slope * t.error_jnd;
      den += w * slope * slope;
      weights += w;
    }
    if (weights <= 0.0 || std::sqrt(den / weights) * std::abs(d) < kMinMeasuredMoveJnd) continue;
    step.change[b] = std::clamp(-num / den, -kMaxAbsorptionStep, kMaxAbsorptionStep);
  }
  return step;
}

}  // namespace room_reverb::core
