// source_directivity: a cardioid-family source g = a + (1 - a) cos(theta) about an axis.
// Directivity shows in the direct sound against the reflections (DRR, the early profile)
// far more than in decay times, and the axis is a direction on the sphere: a coarse grid
// of axes and patterns runs with a fifth of the rays (the early part comes from the exact
// image sources), then the pattern and the azimuth are refined at full rays.
#include <cmath>
#include <limits>
#include <vector>

#include "cause_fitting.h"
#include "room_reverb/common/directions.h"

namespace room_reverb::core {
namespace {

ModelExtension withPattern(double omni_fraction, double azimuth, double elevation) {
  ModelExtension e;
  SourceDirectivity d;
  d.omni_fraction = omni_fraction;
  d.axis = unitVectorFromAngles(azimuth, elevation);
  e.directivity = d;
  return e;
}

}  // namespace

std::optional<FittedCause> fitSourceDirectivity(const FitContext& context, std::string& /*why*/) {
  EvaluationSettings coarse_settings = context.evaluator.settings();
  coarse_settings.simulation.rays.ray_count = std::max<std::size_t>(1000, coarse_settings.simulation.rays.ray_count / 5);
  const ModelEvaluator coarse(context.evaluator.room(), context.evaluator.evidence(), coarse_settings);
  // The grid in one batch, so that the first pattern's traced paths serve the others'
  // replays two at a time (path_ledger.h).
  std::vector<std::pair<double, double>> axes;
  for (int k = 0; k < 6; ++k) axes.emplace_back(k * M_PI / 3.0 - M_PI, 0.0);
  axes.emplace_back(0.0, M_PI / 2.0);
  axes.emplace_back(0.0, -M_PI / 2.0);
  struct GridPoint {
    double a, azimuth, elevation;
  };
  std::vector<GridPoint> grid;
  for (const auto& [azimuth, elevation] : axes) {
    for (double a : {0.3, 0.6}) grid.push_back({a, azimuth, elevation});
  }
  std::vector<ModelExtension> candidates(grid.size(), context.accepted);
  std::vector<ModelEvaluator::EvaluationCase> cases;
  for (std::size_t g = 0; g < grid.size(); ++g) {
    candidates[g].add(withPattern(grid[g].a, grid[g].azimuth, grid[g].elevation));
    cases.push_back({&candidates[g], 0});
  }
  const std::vector<Evaluation> coarse_evaluations = coarse.evaluateMany(cases);
  double best_error = std::numeric_limits<double>::infinity();
  double best_a = 1.0, best_azimuth = 0.0, best_elevation = 0.0;
  for (std::size_t g = 0; g < grid.size(); ++g) {
    const Evaluation& ev = coarse_evaluations[g];
    const double error = ev.valid ? ev.fit_error_jnd : std::numeric_limits<double>::infinity();
    if (error < best_error) {
      best_error = error;
      best_a = grid[g].a;
      best_azimuth = grid[g].azimuth;
      best_elevation = grid[g].elevation;
    }
  }
  const ScalarFit pattern = fitScalar(
      [&](double a) { return evaluateWith(context, withPattern(a, best_azimuth, best_elevation)); },
      std::max(0.0, best_a - 0.3), std::min(1.0, best_a + 0.3), 3, 3);
  ScalarFit fit = pattern;
  double azimuth = best_azimuth;
  if (best_elevation == 0.0) {
    fit = fitScalar([&](double az) { return evaluateWith(context, withPattern(pattern.value, az, 0.0)); },
                    best_azimuth - M_PI / 3.0, best_azimuth + M_PI / 3.0, 3, 3);
    if (fit.evaluation.fit_error_jnd > pattern.evaluation.fit_error_jnd) fit = {best_azimuth, pattern.evaluation};
    azimuth = fit.value;
  }
  // The pattern once more at the refined axis: a and the axis trade off (a narrower
  // pattern slightly off axis reads like a broader one on it).
  double omni_fraction = pattern.value;
  if (best_elevation == 0.0) {
    const ScalarFit again = fitScalar([&](double a) { return evaluateWith(context, withPattern(a, azimuth, 0.0)); },
                                      std::max(0.0, omni_fraction - 0.2), std::min(1.0, omni_fraction + 0.2), 3, 3);
    if (again.evaluation.fit_error_jnd <= fit.evaluation.fit_error_jnd) {
      omni_fraction = again.value;
      fit = again;
    }
  }
  FittedCause cause;
  cause.cause = "source_directivity";
  cause.extension = withPattern(omni_fraction, azimuth, best_elevation);
  cause.parameters.values = {{"omni_fraction", omni_fraction},
                             {"axis_azimuth_deg", std::remainder(azimuth, 2.0 * M_PI) * 180.0 / M_PI},
                             {"axis_elevation_deg", best_elevation * 180.0 / M_PI}};
  cause.evaluation = fit.evaluation;
  return cause;
}

}  // namespace room_reverb::core
