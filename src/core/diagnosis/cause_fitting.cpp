#include "cause_fitting.h"

#include <cmath>
#include <limits>
#include <optional>

#include "room_reverb/common/error.h"
#include "room_reverb/evaluation/simulated_pairs.h"

namespace room_reverb::core {
namespace {

double fitError(const Evaluation& e) { return e.valid ? e.fit_error_jnd : std::numeric_limits<double>::infinity(); }

// The catalogue, once: each cause's id, its fit, how many parameters the fit is free to
// choose (humidity; nine bands; one coefficient; the panel's point, normal and side, its
// material fixed; one factor; decay time and level; pattern and axis; damping), and what
// it means, for readers of the report.
// The physics switches at the end have nothing to fit and cost a simulation per pair (the
// wave one several times the rays' time), so they are tried on request only.
struct CatalogueEntry {
  const char* id;
  std::optional<FittedCause> (*fit)(const FitContext&, std::string&);
  int free_parameters;
  const char* meaning;
  bool by_default = true;
};
constexpr CatalogueEntry kCatalogue[] = {
    {"air_absorption", fitAirAbsorption, 1,
     "the air absorbs high frequencies differently from the model (humidity fitted, ISO 9613-1)"},
    {"surface_absorption", fitSurfaceAbsorption, 9,
     "one surface absorbs differently from the material the model gives it (or, target all_surfaces, every "
     "surface absorbs more or less by the same amount per band)"},
    {"scattering", fitScattering, 1, "the surfaces scatter differently from the model (one coefficient for all)"},
    {"missing_reflector", fitMissingReflector, 6,
     "a reflecting surface the model lacks (placed from the reflection's time and direction)"},
    {"geometry_scale", fitGeometryScale, 1, "the room's dimensions are off by one factor"},
    {"coupled_volume", fitCoupledVolume, 2, "a second, slower decay: a coupled volume the model does not contain"},
    {"source_directivity", fitSourceDirectivity, 3,
     "the source radiates with a directivity the model lacks (cardioid family fitted)"},
    {"low_frequency_modes", fitLowFrequencyModes, 1,
     "below the Schroeder frequency the room rings in modes that rays cannot show (modal synthesis, damping "
     "fitted)"},
    {"diffraction_scattering", fitDiffractionScattering, 0,
     "finite surfaces scatter long waves at their edges, which the materials' coefficients leave out "
     "(Rindel's strip model, nothing fitted)",
     false},
    {"wave_low_band", fitWaveLowBand, 0,
     "the low band is a wave field, which rays cannot show (wave solver below the crossover, nothing fitted)",
     false},
    {"third_octave_bands", fitThirdOctaveBands, 0,
     "an octave's coefficient averages over thirds that differ (the materials' third-octave coefficients, "
     "simulated and synthesised per third, nothing fitted)",
     false}};

const CatalogueEntry& entry(const std::string& cause) {
  for (const CatalogueEntry& e : kCatalogue) {
    if (cause == e.id) return e;
  }
  std::string known;
  for (const CatalogueEntry& e : kCatalogue) known += (known.empty() ? "" : ", ") + std::string(e.id);
  throw InputError("unknown cause '" + cause + "'; the catalogue has " + known);
}

std::vector<std::string> catalogueIds(bool by_default) {
  std::vector<std::string> ids;
  for (const CatalogueEntry& e : kCatalogue) {
    if (e.by_default == by_default) ids.emplace_back(e.id);
  }
  return ids;
}

}  // namespace

const std::vector<std::string> kCatalogueCauses = catalogueIds(true);
const std::vector<std::string> kOnRequestCauses = catalogueIds(false);

void requireKnownCause(const std::string& cause) { entry(cause); }

CauseFitter causeFitter(const std::string& cause) { return entry(cause).fit; }

int freeParameters(const std::string& cause) { return entry(cause).free_parameters; }

std::string causeMeaning(const std::string& cause) { return entry(cause).meaning; }

Evaluation evaluateWith(const FitContext& context, const ModelExtension& extension) {
  ModelExtension combined = context.accepted;
  combined.add(extension);
  return context.evaluator.evaluate(combined);
}

std::vector<Evaluation> evaluateWithEach(const FitContext& context, const std::vector<ModelExtension>& extensions) {
  std::vector<ModelExtension> combined(extensions.size(), context.accepted);
  std::vector<ModelEvaluator::EvaluationCase> cases;
  for (std::size_t k = 0; k < extensions.size(); ++k) {
    combined[k].add(extensions[k]);
    cases.push_back({&combined[k], 0});
  }
  return context.evaluator.evaluateMany(cases);
}

std::function<std::vector<Evaluation>(const std::vector<double>&)> evaluateEachOf(
    const FitContext& context, const std::function<ModelExtension(double)>& make) {
  return [&context, make](const std::vector<double>& xs) {
    std::vector<ModelExtension> extensions;
    for (double x : xs) extensions.push_back(make(x));
    return evaluateWithEach(context, extensions);
  };
}

Evaluation reanalyseWith(const FitContext& context, const ModelExtension& extension, const ModalRoom* modal_room) {
  const ModelEvaluator& evaluator = context.evaluator;
  // The coupled decay is the last response effect: a candidate with only that is added to
  // the responses as they are now (the accepted modes already in them, not synthesised
  // again for every candidate); a candidate with modes starts again from the raw ones.
  const bool on_top = !extension.modes && !context.accepted.coupled;
  ModelExtension combined = context.accepted;
  combined.add(extension);
  std::optional<ModalRoom> own_room;
  if (!on_top && combined.modes && !modal_room) {
    own_room = modalRoomFor(evaluator.room().scene(context.accepted), evaluator.room().airWith(context.accepted));
    modal_room = &*own_room;
  }
  Evaluation evaluation;
  try {
    const std::vector<PairPrediction>& bases = context.current.predictions;
    evaluation.predictions = bases;
    runInRounds(bases.size(), evaluator.settings().simulation.rays.threads, [&](std::size_t i, int) {
      const PairPrediction& base = bases[i];
      const MeasurementPair& pair = base.analysis.pair;
      const AudioBuffer extended = on_top ? extendedResponse(base.analysis.omni, base, pair, extension, nullptr)
                                          : extendedResponse(base.simulated_omni, base, pair, combined, modal_room);
      PairPrediction& prediction = evaluation.predictions[i];
      prediction.analysis = analysePair(pair, extended);
      prediction.analysis.directions = predictedDirections(extended, prediction);
    });
  } catch (const InputError& e) {
    evaluation.reason = e.what();
    return evaluation;
  }
  score(evaluation, evaluator.evidence(), evaluator.settings());
  return evaluation;
}

ScalarFit fitScalar(const std::function<Evaluation(double)>& evaluate, double lo, double hi, int grid, int refinements,
                    const std::function<std::vector<Evaluation>(const std::vector<double>&)>& evaluate_grid) {
  if (grid < 3) throw InputError("fitScalar: need at least three grid points");
  std::vector<double> xs(static_cast<std::size_t>(grid));
  std::vector<double> errors(xs.size());
  ScalarFit best;
  double best_error = std::numeric_limits<double>::infinity();
  std::size_t best_index = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    xs[i] = lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(grid - 1);
  }
  std::vector<Evaluation> at_grid;
  if (evaluate_grid) {
    at_grid = evaluate_grid(xs);
  } else {
    for (double x : xs) at_grid.push_back(evaluate(x));
  }
  for (std::size_t i = 0; i < xs.size(); ++i) {
    Evaluation& e = at_grid[i];
    errors[i] = fitError(e);
    if (errors[i] < best_error) {
      best_error = errors[i];
      best_index = i;
      best = {xs[i], std::move(e)};
    }
  }
  if (refinements <= 0) return best;
  // Golden-section search inside the grid cell pair around the best point.
  double a = xs[best_index > 0 ? best_index - 1 : 0];
  double b = xs[std::min(best_index + 1, xs.size() - 1)];
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - ratio * (b - a), d = a + ratio * (b - a);
  Evaluation ec = evaluate(c), ed = evaluate(d);
  for (int step = 0; step < refinements; ++step) {
    if (fitError(ec) < best_error) { best_error = fitError(ec); best = {c, ec}; }
    if (fitError(ed) < best_error) { best_error = fitError(ed); best = {d, ed}; }
    if (step + 1 == refinements) break;
    if (fitError(ec) < fitError(ed)) {
      b = d; d = c; ed = std::move(ec);
      c = b - ratio * (b - a);
      ec = evaluate(c);
    } else {
      a = c; c = d; ec = std::move(ed);
      d = a + ratio * (b - a);
      ed = evaluate(d);
    }
  }
  return best;
}

}  // namespace room_reverb::core
