// missing_reflector: a strong early reflection in a measured B-format RIR that no specular
// path of the model explains is taken as a surface the model lacks, placed by image-source
// geometry from its time and direction (unexplained_reflections.h). Points found at several fit pairs are clustered; the panel (a thin cuboid, upright or
// level, whichever the normal is closer to) goes where most agree, and its size is fitted.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "cause_fitting.h"
#include "room_reverb/acoustics/propagation.h"
#include "room_reverb/common/directions.h"
#include "room_reverb/evaluation/unexplained_reflections.h"

namespace room_reverb::core {
namespace {

constexpr double kClusterRadiusM = 0.6;
constexpr double kPanelThicknessM = 0.04;
constexpr const char* kPanelMaterial = "wood_panel";

using ReflectionPoint = UnexplainedReflection;

// The unexplained reflections of the fit pairs (held-out pairs do not place the panel).
std::vector<ReflectionPoint> unexplainedPoints(const FitContext& context, double speed_of_sound) {
  const MeasuredEvidence& evidence = context.evaluator.evidence();
  const AcousticScene scene = context.evaluator.room().scene(context.accepted);
  std::vector<ReflectionPoint> points;
  const bool split = evidence.rirs.size() >= 2;
  for (std::size_t i = 0; i < evidence.rirs.size() && i < context.current.predictions.size(); ++i) {
    if ((split && i % 2 == 1) || !evidence.rirs[i].rsao) continue;
    const auto found = unexplainedReflections(relativeReflections(*evidence.rirs[i].rsao), context.current.predictions[i].paths,
                                              evidence.rirs[i].pair, scene, speed_of_sound);
    points.insert(points.end(), found.begin(), found.end());
  }
  return points;
}

// The largest group of points within kClusterRadiusM of one member and facing its way;
// between groups of one size, the one with the most reflected energy.
std::vector<ReflectionPoint> largestCluster(const std::vector<ReflectionPoint>& points) {
  std::vector<ReflectionPoint> best;
  double best_energy = 0.0;
  for (const ReflectionPoint& seed : points) {
    std::vector<ReflectionPoint> group;
    double energy = 0.0;
    for (const ReflectionPoint& p : points) {
      if ((p.point - seed.point).norm() <= kClusterRadiusM && p.normal.dot(seed.normal) > 0.7) {
        group.push_back(p);
        energy += std::pow(10.0, p.level_db / 10.0);
      }
    }
    if (group.size() > best.size() || (group.size() == best.size() && energy > best_energy)) {
      best = group;
      best_energy = energy;
    }
  }
  return best;
}

CuboidObject panelAt(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size_m) {
  CuboidObject panel;
  panel.label = "fitted_reflector";
  panel.material = kPanelMaterial;
  if (std::abs(normal.z()) > std::sqrt(0.5)) {
    // Closer to level: a horizontal panel (a table top, a canopy) below or above the point.
    const double side = normal.z() > 0.0 ? -1.0 : 1.0;
    panel.size_m = {size_m, size_m, kPanelThicknessM};
    panel.center_m = point + Eigen::Vector3d(0, 0, side * 0.5 * kPanelThicknessM);
  } else {
    const Eigen::Vector3d horizontal = Eigen::Vector3d(normal.x(), normal.y(), 0.0).normalized();
    panel.yaw_rad = std::atan2(horizontal.y(), horizontal.x());
    panel.size_m = {kPanelThicknessM, size_m, size_m};
    panel.center_m = point - horizontal * 0.5 * kPanelThicknessM;
  }
  return panel;
}

}  // namespace

std::optional<FittedCause> fitMissingReflector(const FitContext& context, std::string& why) {
  const double c = speedOfSoundMPerS(context.evaluator.room().airWith(context.accepted).temperature_c);
  const std::vector<ReflectionPoint> cluster = largestCluster(unexplainedPoints(context, c));
  if (cluster.empty()) {
    why = context.evaluator.evidence().rirs.empty() || !context.evaluator.evidence().rirs.front().rsao
              ? "needs B-format measurements (reflection directions)"
              : "every strong early reflection has a specular path in the model";
    return std::nullopt;
  }
  Eigen::Vector3d point = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
  for (const ReflectionPoint& p : cluster) {
    point += p.point;
    normal += p.normal;
  }
  point /= static_cast<double>(cluster.size());
  normal.normalize();
  const auto make = [&](double size) {
    ModelExtension e;
    e.reflectors.push_back(panelAt(point, normal, size));
    return e;
  };
  const ScalarFit fit = fitScalar([&](double size) { return evaluateWith(context, make(size)); }, 0.5, 1.5, 3, 0);
  FittedCause cause;
  cause.cause = "missing_reflector";
  cause.target = "fitted_reflector";
  cause.extension = make(fit.value);
  cause.parameters.values = {{"x_m", point.x()}, {"y_m", point.y()}, {"z_m", point.z()},
                             {"normal_x", normal.x()}, {"normal_y", normal.y()}, {"normal_z", normal.z()},
                             {"size_m", fit.value}, {"supporting_reflections", static_cast<double>(cluster.size())}};
  cause.parameters.text["material"] = kPanelMaterial;
  cause.evaluation = fit.evaluation;
  return cause;
}

}  // namespace room_reverb::core
