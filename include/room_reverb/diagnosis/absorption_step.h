#pragma once
// One Gauss-Newton step for the absorption a surface-absorption fit adds to its target, per
// octave band, from evaluations of the same seed at other absorptions: the sensitivity of
// every fit term (decay times, EDT, C80, D50, DRR, early windows) is measured, not assumed.
//
// Why measured: Sabine's T ~ V / A holds where the sound field is diffuse. In the sample
// room (absorbing ceiling, hard walls) the late decay is carried by sound running between
// the walls, and the floor's absorption at 2 kHz going from 0.60 to 0.06 moved T20 by 4 %
// where Sabine predicts 30 %, while DRR moved 1.4 dB (docs/validation/diagnosis.md). A
// step from Sabine's slope there is driven by decay noise; one from the measured slope
// follows whatever the surface does move.
#include <optional>
#include <vector>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/diagnosis/model_evaluation.h"

namespace room_reverb::core {

// An evaluation at an absorption offset (added per band to the target's absorption).
struct OffsetEvaluation {
  OctaveBandValues offset{};
  const Evaluation* evaluation = nullptr;
};

struct AbsorptionStep {
  // Per band (standardBands(kOctave) order): the offset change, or empty where no fit term
  // of the band moved measurably between the evaluations (bands without fit terms: 63 Hz,
  // 16 kHz, the held-out bands of a band split).
  std::vector<std::optional<double>> change;
};

// Smallest root-mean-square move (JND) of a band's fit terms between two evaluations for
// the band's slope to count as measured rather than noise.
constexpr double kMinMeasuredMoveJnd = 0.05;
// Largest offset change of one step per band: the terms are not linear over more.
constexpr double kMaxAbsorptionStep = 0.4;

// The step from `at`: per band, the slope of each fit term is the secant to the other
// evaluation whose offset differs most from `at` in that band; the step minimises the
// fit terms' squares, each weighted by one over its group's term count (the fit error
// averages each group's terms, then the groups), linearised. Terms at the cap
// (kTermCapJnd) in either evaluation and the reflection term are left out.
AbsorptionStep gaussNewtonAbsorptionStep(const OffsetEvaluation& at, const std::vector<OffsetEvaluation>& others);

}  // namespace room_reverb::core
