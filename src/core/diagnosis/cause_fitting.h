#pragma once
// The hypotheses of the diagnosis (diagnosis.h), each fitting its extension's parameters
// on the fit part of the evidence, on top of the extensions already accepted. Private to
// the evaluation module.
#include <functional>
#include <optional>
#include <string>

#include "room_reverb/diagnosis/diagnosis.h"

namespace room_reverb::core {

struct FitContext {
  const ModelEvaluator& evaluator;
  const ModelExtension& accepted;    // extensions already named
  const Evaluation& current;         // the evaluation of `accepted`
  double noise_jnd = 0.0;            // the held-out error's noise over seeds (Diagnosis::noise_jnd):
                                     // fits whose errors differ by less are tied
};

struct FittedCause {
  std::string cause, target;
  CauseParameters parameters;
  ModelExtension extension;  // this cause alone (to be added to `accepted`)
  Evaluation evaluation;     // of accepted + extension
};

// Each returns nothing when the hypothesis does not apply (e.g. no B-format evidence to
// place a reflector from); `why` then says so.
using CauseFitter = std::function<std::optional<FittedCause>(const FitContext&, std::string& why)>;
CauseFitter causeFitter(const std::string& cause);  // InputError for an unknown id

std::optional<FittedCause> fitAirAbsorption(const FitContext& context, std::string& why);
std::optional<FittedCause> fitSurfaceAbsorption(const FitContext& context, std::string& why);
std::optional<FittedCause> fitScattering(const FitContext& context, std::string& why);
std::optional<FittedCause> fitMissingReflector(const FitContext& context, std::string& why);
std::optional<FittedCause> fitGeometryScale(const FitContext& context, std::string& why);
std::optional<FittedCause> fitCoupledVolume(const FitContext& context, std::string& why);
std::optional<FittedCause> fitThirdOctaveBands(const FitContext& context, std::string& why);
std::optional<FittedCause> fitSourceDirectivity(const FitContext& context, std::string& why);
std::optional<FittedCause> fitLowFrequencyModes(const FitContext& context, std::string& why);
std::optional<FittedCause> fitDiffractionScattering(const FitContext& context, std::string& why);
std::optional<FittedCause> fitWaveLowBand(const FitContext& context, std::string& why);

// The evaluation of accepted + extension.
Evaluation evaluateWith(const FitContext& context, const ModelExtension& extension);
// evaluateWith for each extension, in one batch (ModelEvaluator::evaluateMany): with a
// runner, the candidates are simulated together.
std::vector<Evaluation> evaluateWithEach(const FitContext& context, const std::vector<ModelExtension>& extensions);
// For fitScalar's grid: evaluateWithEach of make(x) for every value x.
std::function<std::vector<Evaluation>(const std::vector<double>&)> evaluateEachOf(
    const FitContext& context, const std::function<ModelExtension(double)>& make);
// The same for an extension that acts only on responses (modes, a coupled decay): the
// responses simulated for `current` are re-analysed, nothing is simulated again. The
// modal room is built from the accepted scene when none is given and one is needed.
Evaluation reanalyseWith(const FitContext& context, const ModelExtension& extension, const ModalRoom* modal_room = nullptr);

// One-parameter fit: a grid of `grid` points over [lo, hi], then golden-section steps in
// the bracket around the best grid point; minimises the fit error. Returns the best
// parameter and its evaluation (invalid evaluations count as infinitely bad).
struct ScalarFit {
  double value = 0.0;
  Evaluation evaluation;
};
// `evaluate_grid` (may be empty): the evaluations of several values at once, for the grid
// (evaluateWithEach, so that a runner simulates the grid together); the same results as
// `evaluate` for each value.
ScalarFit fitScalar(const std::function<Evaluation(double)>& evaluate, double lo, double hi, int grid = 5,
                    int refinements = 5,
                    const std::function<std::vector<Evaluation>(const std::vector<double>&)>& evaluate_grid = {});

}  // namespace room_reverb::core
