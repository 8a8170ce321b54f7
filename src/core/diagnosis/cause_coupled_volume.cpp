// coupled_volume: a room coupled to a second, more reverberant volume decays in two slopes
// (Cremer and Mueller; Xiang's two-slope analysis): the main room's decay first, then the
// coupled volume's slower one showing once the first has fallen below it. The extension
// adds that second decay to the simulated late response (model_evaluation.h); its decay
// time and level are fitted on a grid by re-analysing the simulated responses already at
// hand, since adding the tail needs no new simulation.
#include <cmath>
#include <limits>

#include "cause_fitting.h"

namespace room_reverb::core {
namespace {

// The measured decay time that the grid of coupled decay times is scaled by: mid-band
// T20 (500 Hz and 1 kHz) of the evidence.
double midBandDecayTime(const MeasuredEvidence& evidence) {
  double sum = 0.0;
  int n = 0;
  const auto take = [&](double band_hz, const std::optional<double>& t20) {
    if ((band_hz == 500.0 || band_hz == 1000.0) && t20) {
      sum += *t20;
      ++n;
    }
  };
  for (const PairEvidence& pair : evidence.rirs) {
    for (const AcousticParameters& band : pair.metrics.bands) take(band.nominal_hz, band.t20_s);
  }
  for (std::size_t b = 0; b < evidence.table.bands_hz.size() && !evidence.table.t20_s.empty(); ++b) {
    take(evidence.table.bands_hz[b], evidence.table.t20_s[b]);
  }
  return n > 0 ? sum / n : 0.0;
}

}  // namespace

std::optional<FittedCause> fitCoupledVolume(const FitContext& context, std::string& why) {
  if (context.accepted.coupled) {
    why = "a coupled decay is already part of the model";
    return std::nullopt;
  }
  const double t_main = midBandDecayTime(context.evaluator.evidence());
  if (!(t_main > 0.0)) {
    why = "no measured mid-band T20 to scale the coupled decay by";
    return std::nullopt;
  }
  std::optional<FittedCause> best;
  double best_error = std::numeric_limits<double>::infinity();
  for (double factor : {1.5, 2.0, 2.5, 3.0, 4.0}) {
    for (double level_db = -15.0; level_db <= 15.0; level_db += 5.0) {
      const CoupledDecay decay{factor * t_main, level_db};
      ModelExtension extension;
      extension.coupled = decay;
      Evaluation evaluation = reanalyseWith(context, extension);
      if (evaluation.fit_error_jnd >= best_error) continue;
      best_error = evaluation.fit_error_jnd;
      FittedCause cause;
      cause.cause = "coupled_volume";
      cause.extension.coupled = decay;
      cause.parameters.values = {{"coupled_t60_s", decay.t60_s}, {"coupled_level_db", decay.level_db}};
      cause.evaluation = std::move(evaluation);
      best = std::move(cause);
    }
  }
  return best;
}

}  // namespace room_reverb::core
