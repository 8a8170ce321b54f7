// The surface-absorption fit's Gauss-Newton step (absorption_step.h) on error terms that are
// linear in the absorption offset with a planted optimum: the step must land on it, weigh
// groups as the fit error does, and leave alone what it cannot measure.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "room_reverb/diagnosis/absorption_step.h"

namespace room_reverb::core {
namespace {

// One linear term: error = slope * (offset - optimum) in JND, at band `band_hz`.
struct LinearTerm {
  std::string group;
  double band_hz;
  int window;
  double slope, optimum;
  bool held_out = false;
};

Evaluation evaluateAt(const std::vector<LinearTerm>& terms, const OctaveBandValues& offset) {
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  Evaluation e;
  e.valid = true;
  for (const LinearTerm& t : terms) {
    std::size_t b = 0;
    while (bands[b].nominal_hz != t.band_hz) ++b;
    ErrorTerm term;
    term.pair = 0;
    term.group = t.group;
    term.band_hz = t.band_hz;
    term.window = t.window;
    term.error_jnd = t.slope * (offset[b] - t.optimum);
    term.held_out = t.held_out;
    e.terms.push_back(term);
  }
  return e;
}

OctaveBandValues uniformOffset(double x) {
  OctaveBandValues o{};
  o.fill(x);
  return o;
}

constexpr std::size_t k500 = 3, k1000 = 4, k2000 = 5;  // band indices from 63 Hz

TEST(AbsorptionStep, LandsOnAPlantedOptimumPerBandFromOneProbe) {
  // DRR and four early windows at 500 Hz and 2 kHz, with different optima per band.
  std::vector<LinearTerm> terms;
  for (const double band : {500.0, 2000.0}) {
    const double optimum = band == 500.0 ? 0.12 : -0.3;
    terms.push_back({"DRR", band, -1, -8.0, optimum});
    for (int w = 1; w <= 4; ++w) terms.push_back({"early", band, w, 5.0 + w, optimum});
  }
  const Evaluation at = evaluateAt(terms, uniformOffset(0.0));
  const Evaluation probe = evaluateAt(terms, uniformOffset(0.1));
  const AbsorptionStep step = gaussNewtonAbsorptionStep({uniformOffset(0.0), &at}, {{uniformOffset(0.1), &probe}});
  ASSERT_TRUE(step.change[k500] && step.change[k2000]);
  EXPECT_NEAR(*step.change[k500], 0.12, 1e-9);
  EXPECT_NEAR(*step.change[k2000], -0.3, 1e-9);
  // Bands without terms are left to the caller (interpolated between neighbours).
  EXPECT_FALSE(step.change[0]);
  EXPECT_FALSE(step.change[k1000]);
}

TEST(AbsorptionStep, WeighsEachGroupAsTheFitErrorDoes) {
  // One DRR term wants +0.2, four early windows want 0: weighted one over the group's
  // count, the two groups pull equally and the step is 0.1 (unweighted it would be 0.04).
  std::vector<LinearTerm> terms{{"DRR", 1000.0, -1, 1.0, 0.2}};
  for (int w = 1; w <= 4; ++w) terms.push_back({"early", 1000.0, w, 1.0, 0.0});
  const Evaluation at = evaluateAt(terms, uniformOffset(0.0));
  const Evaluation probe = evaluateAt(terms, uniformOffset(0.1));
  const AbsorptionStep step = gaussNewtonAbsorptionStep({uniformOffset(0.0), &at}, {{uniformOffset(0.1), &probe}});
  ASSERT_TRUE(step.change[k1000]);
  EXPECT_NEAR(*step.change[k1000], 0.1, 1e-9);
}

TEST(AbsorptionStep, IgnoresHeldOutCappedAndReflectionTermsAndNoiseLevelSlopes) {
  std::vector<LinearTerm> terms{{"T20", 1000.0, -1, 4.0, 0.05},
                                {"T20", 1000.0, -1, 4.0, -0.2, true},  // held out: must not steer
                                {"reflections", 1000.0, -1, 10.0, 0.3},  // judges, does not steer
                                {"C80", 1000.0, -1, 200.0, 0.0},          // at the cap: no slope
                                {"T20", 500.0, -1, 0.2, 0.3}};            // moves 0.02 JND per 0.1: noise
  const Evaluation at = evaluateAt(terms, uniformOffset(0.0));
  const Evaluation probe = evaluateAt(terms, uniformOffset(0.1));
  const AbsorptionStep step = gaussNewtonAbsorptionStep({uniformOffset(0.0), &at}, {{uniformOffset(0.1), &probe}});
  ASSERT_TRUE(step.change[k1000]);
  EXPECT_NEAR(*step.change[k1000], 0.05, 1e-9);
  EXPECT_FALSE(step.change[k500]);
}

TEST(AbsorptionStep, IsLimitedAndUsesTheFarthestEvaluationPerBand) {
  // The optimum is 0.9 away: one step goes at most kMaxAbsorptionStep.
  const std::vector<LinearTerm> far{{"EDT", 2000.0, -1, 3.0, 0.9}};
  const Evaluation at = evaluateAt(far, uniformOffset(0.0));
  const Evaluation probe = evaluateAt(far, uniformOffset(0.1));
  const AbsorptionStep limited = gaussNewtonAbsorptionStep({uniformOffset(0.0), &at}, {{uniformOffset(0.1), &probe}});
  ASSERT_TRUE(limited.change[k2000]);
  EXPECT_DOUBLE_EQ(*limited.change[k2000], kMaxAbsorptionStep);

  // A second step from 0.4 with a curved term (the error grows with the square root of the
  // distance to 0.5), so that the secants to 0 and to 0.1 differ (steps of 0.32 and 0.30):
  // the one to the farthest evaluation, 0, is used.
  auto curved = [](double x) {
    Evaluation e;
    e.valid = true;
    ErrorTerm t;
    t.group = "EDT";
    t.band_hz = 2000.0;
    t.error_jnd = 3.0 * std::copysign(std::sqrt(std::abs(x - 0.5)), x - 0.5);
    e.terms.push_back(t);
    return e;
  };
  const Evaluation e0 = curved(0.0), e1 = curved(0.1), e4 = curved(0.4);
  const AbsorptionStep second =
      gaussNewtonAbsorptionStep({uniformOffset(0.4), &e4}, {{uniformOffset(0.0), &e0}, {uniformOffset(0.1), &e1}});
  ASSERT_TRUE(second.change[k2000]);
  const double secant_to_0 = (e0.terms[0].error_jnd - e4.terms[0].error_jnd) / (0.0 - 0.4);
  EXPECT_NEAR(*second.change[k2000], -e4.terms[0].error_jnd / secant_to_0, 1e-9);
}

TEST(AbsorptionStep, AnInvalidEvaluationGivesNoStep) {
  const std::vector<LinearTerm> terms{{"T20", 1000.0, -1, 4.0, 0.05}};
  Evaluation at = evaluateAt(terms, uniformOffset(0.0));
  Evaluation probe = evaluateAt(terms, uniformOffset(0.1));
  probe.valid = false;
  const AbsorptionStep no_probe = gaussNewtonAbsorptionStep({uniformOffset(0.0), &at}, {{uniformOffset(0.1), &probe}});
  for (const auto& c : no_probe.change) EXPECT_FALSE(c);
  at.valid = false;
  probe.valid = true;
  const AbsorptionStep no_start = gaussNewtonAbsorptionStep({uniformOffset(0.0), &at}, {{uniformOffset(0.1), &probe}});
  for (const auto& c : no_start.change) EXPECT_FALSE(c);
}

}  // namespace
}  // namespace room_reverb::core
