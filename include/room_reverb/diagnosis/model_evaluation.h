#pragma once
// Simulating a (possibly extended) model at every measured pair and scoring it against the
// measurement in just-noticeable differences, on evidence split into a part a fit may use
// and a part it may not (held out), so that every cause's gain is measured on evidence its
// parameters never saw.
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/acoustics/simulation_runner.h"
#include "room_reverb/evaluation/measured_evidence.h"
#include "room_reverb/diagnosis/model_extension.h"
#include "room_reverb/diagnosis/response_extensions.h"

namespace room_reverb::core {

struct EvaluationSettings {
  SimulationSettings simulation;  // omni; its seed is the base seed of every evaluation
  std::vector<double> bands_hz{125, 250, 500, 1000, 2000, 4000, 8000};
  EarlyEnergyOptions early;
  // Score the `reflections` term (reflection_evidence.h) for two or more B-format pairs: it
  // judges fits on the held-out pairs and does not steer them (the fit error leaves it
  // out). Without it a missing panel that one held-out pair hears at -7 dB moves the
  // averaged decay and early-energy terms too little to be named (docs/diagnosis.md).
  bool score_reflections = true;
  // Score the `directions` group (early_direction.h) for B-format measurements: the
  // simulations are then first order. Without it the decay, clarity, DRR and early-energy
  // terms (all omni) see only how much absorption a surface adds, not which surface: four
  // pairs put a planted absorbing wall on the right surface in 2 of 7 rooms.
  bool score_directions = true;
  // Where the simulations run (simulation_runner.h): null, this process. Worker processes
  // or room_simulator nodes give the same evaluations, to the bit.
  std::shared_ptr<SimulationRunner> runner;
  // Keep the ray tracer's paths of the first model traced at each pair's base seed (in this
  // process)
  // and answer a model that differs from it only in absorption, air or source directivity
  // by replaying them (path_ledger.h) instead of tracing: the absorption, humidity and
  // directivity fits then cost their image sources and synthesis. A replay has the same
  // expectation as a trace and shares its seed's paths, so a fit's candidates differ only
  // by what they change (docs/simulation.md).
  bool replay_paths = true;
};

// One number of the comparison: parameter `group` (T20, T30, EDT, C80, D50, DRR, early or
// directions) in one band (and, for `early`, one window; for `directions`, one of the six
// steering directions of early_direction.h) of one pair (-1: the averaged table);
// or, with score_reflections and two or more B-format measurements, `reflections` (band 0):
// the pair's strong measured reflections that no path of the model explains
// (reflection_evidence.h).
struct ErrorTerm {
  int pair = -1;
  std::string group;
  double band_hz = 0.0;
  int window = -1;
  double error_jnd = 0.0;  // signed
  bool held_out = false;
};

struct PairPrediction {
  PairEvidence analysis;              // the simulated response, extended, analysed as a measured one
                                      // (its omni channel; `directions` from all four, see evaluate())
  std::vector<SpecularPath> paths;    // the model's specular arrivals at this pair
  std::vector<float> simulated_omni;  // as simulated, before the response extensions
  // First-order simulations (EvaluationSettings::score_directions): X, Y, Z (ACN 1-3 as
  // simulated) up to 20 ms past the directions' window, which a re-analysis needs again.
  std::vector<std::vector<float>> simulated_velocity;
  std::uint32_t seed = 0;             // of the ray tracing (and of a coupled decay's noise)
  // B-format measurements: the reflection term of the paths (reflection_evidence.h). The
  // response extensions leave the paths as they are, so it stands for them too.
  std::optional<double> reflection_error_jnd;
};

struct Evaluation {
  bool valid = false;
  std::string reason;  // why not (e.g. a pair outside the scaled room)
  std::vector<PairPrediction> predictions;
  std::vector<ErrorTerm> terms;
  double error_jnd = 0.0;          // all evidence
  double fit_error_jnd = 0.0;      // the part fits may use
  double heldout_error_jnd = 0.0;  // the part they may not
};

// With two or more measured pairs the evidence is split by pair: indices 0, 2, 4... fit
// and 1, 3, 5... are held out. One pair, or a table of parameters averaged over pairs, is
// split by octave band instead: 125, 500, 2000 and 8000 Hz fit, 63, 250, 1000, 4000 and
// 16000 Hz are held out. A split by parameter (fit on T20, judge on EDT) cannot tell a
// physical cause from one that is free in every band: nine per-band absorptions fitted on
// T20 predict EDT in the same bands as well as the air's two parameters do (CR2, session
// 8). Split by band, a per-band fit must interpolate, and is credited only for what it
// predicts between the bands it saw.
inline bool splitsByPair(std::size_t pair_count) { return pair_count >= 2; }
inline bool isHeldOutPair(std::size_t pair) { return pair % 2 == 1; }
inline bool isHeldOutBand(double nominal_hz) {
  const long octaves_from_125 = std::lround(std::log2(nominal_hz / 125.0));
  return octaves_from_125 % 2 != 0;
}

// No term counts more than this, so that one wild value cannot outweigh the rest.
constexpr double kTermCapJnd = 10.0;

// Mean absolute error in JND over the terms selected (each term capped at kTermCapJnd, a
// pair's reflection term per reflection): each parameter group's mean, then the mean over
// the groups, so that no group counts more for having more numbers.
double meanAbsoluteError(const std::vector<ErrorTerm>& terms, int selection);  // -1 all, 0 fit, 1 held out
// The per-group means that meanAbsoluteError averages.
std::map<std::string, double> groupMeanAbsoluteErrors(const std::vector<ErrorTerm>& terms, int selection);

// The error terms of predictions against evidence.
std::vector<ErrorTerm> errorTerms(const MeasuredEvidence& evidence, const std::vector<PairPrediction>& predictions,
                                  const EvaluationSettings& settings);

class ModelEvaluator {
 public:
  ModelEvaluator(const RoomUnderTest& room, const MeasuredEvidence& evidence, EvaluationSettings settings);
  // Simulates with the extension; `seed_offset` changes the ray tracing's noise (to measure
  // the noise of the error itself). Never throws for a model the extension made impossible
  // (a pair outside the room): returns valid = false with the reason.
  Evaluation evaluate(const ModelExtension& extension, std::uint32_t seed_offset = 0) const;
  // evaluate() of each case. With a runner, every pair of every case is one batch, so that
  // up to pairs x cases simulators work at once; in this process the cases run one after
  // another. The evaluations are the same either way. Cases that point to the same
  // extension one after another share its scene.
  struct EvaluationCase {
    const ModelExtension* extension = nullptr;
    std::uint32_t seed_offset = 0;
  };
  std::vector<Evaluation> evaluateMany(const std::vector<EvaluationCase>& cases) const;
  // evaluateMany() of one extension at each seed offset.
  std::vector<Evaluation> evaluateAtSeeds(const ModelExtension& extension,
                                          const std::vector<std::uint32_t>& seed_offsets) const;
  const RoomUnderTest& room() const { return room_; }
  const MeasuredEvidence& evidence() const { return evidence_; }
  const EvaluationSettings& settings() const { return settings_; }
  int evaluations() const { return evaluations_; }
  // Pair simulations answered by replaying kept paths instead of tracing.
  int replayedSimulations() const { return replayed_; }

 private:
  const RoomUnderTest& room_;
  const MeasuredEvidence& evidence_;
  EvaluationSettings settings_;
  // The given model's scene: where a measured reflection could come from a missing surface
  // (reflection_evidence.h) is judged in it for every candidate alike, so a candidate can
  // lower the reflection term only by explaining reflections with paths, not by putting a
  // surface next to their points.
  std::shared_ptr<const AcousticScene> given_scene_;
  bool score_directions_ = false;  // settings' score_directions and a measured profile to score
  mutable int evaluations_ = 0;
  mutable int replayed_ = 0;
  // The paths kept per (ray-tracing seed, pair): the first model traced there at the base
  // seed, all together at most kKeptPathsBudgetBytes (the sample room at 10 000 rays and
  // 1.5 s keeps 42 MB per pair).
  static constexpr std::size_t kKeptPathsBudgetBytes = std::size_t{512} << 20;
  mutable std::map<std::pair<std::uint32_t, std::size_t>, SimulationResult> kept_paths_;
  mutable std::size_t kept_bytes_ = 0;
  struct PreparedCase;
  // The case's scene and requests (the scene and settings of `same_model` when given: the
  // same extension at another seed).
  PreparedCase prepare(const EvaluationCase& c, const PreparedCase* same_model) const;
  // The case's evaluation from its pairs' results (moved from), scored.
  // Pair i's simulated response analysed as its measurement is.
  void predictPair(const PreparedCase& prepared, std::size_t i, SimulationResult& result, PairPrediction& prediction) const;
};

// Marks the evaluation valid and scores its predictions: terms and the three errors.
void score(Evaluation& evaluation, const MeasuredEvidence& evidence, const EvaluationSettings& settings);

// `omni_response` (the prediction's simulated response, or one already extended) with the
// extension's response effects (response_extensions.h) applied, at the prediction's
// direct-sound delay and seed: what its analysis is made from.
AudioBuffer extendedResponse(const std::vector<float>& omni_response, const PairPrediction& prediction,
                             const MeasurementPair& pair, const ModelExtension& extension, const ModalRoom* modal_room);

// The directions profile (early_direction.h) of a prediction: W as `extended` (the
// response extensions act on the omni channel: a coupled decay is diffuse, the modes lie
// below the profile's bands), X, Y, Z as simulated; empty without simulated_velocity.
std::optional<EarlyDirectionProfile> predictedDirections(const AudioBuffer& extended, const PairPrediction& prediction);

}  // namespace room_reverb::core
