// missing_reflector: a strong early reflection in a measured B-format RIR that no specular
// path of the model explains is taken as a surface the model lacks, placed by image-source
// geometry from its time and direction (unexplained_reflections.h). Points found at
// several fit pairs are clustered; the panel (a thin cuboid, upright or level) goes where
// most agree, over the extent the fit pairs' geometry allows (panel_extent.h).
#include <cmath>

#include "cause_fitting.h"
#include "room_reverb/acoustics/propagation.h"
#include "room_reverb/common/directions.h"
#include "room_reverb/diagnosis/panel_extent.h"
#include "room_reverb/diagnosis/unexplained_reflections.h"

namespace room_reverb::core {
namespace {

constexpr double kClusterRadiusM = 0.6;
constexpr double kPanelThicknessM = 0.04;
constexpr const char* kPanelMaterial = "wood_panel";

using ReflectionPoint = UnexplainedReflection;

// The fit pairs with an RSAO (held-out pairs neither place nor bound the panel), with
// their measured reflections and the model's paths.
std::vector<PanelWitness> fitWitnesses(const FitContext& context) {
  const MeasuredEvidence& evidence = context.evaluator.evidence();
  std::vector<PanelWitness> witnesses;
  for (std::size_t i = 0; i < evidence.rirs.size() && i < context.current.predictions.size(); ++i) {
    if ((splitsByPair(evidence.rirs.size()) && isHeldOutPair(i)) || !evidence.rirs[i].rsao) continue;
    witnesses.push_back({evidence.rirs[i].pair, relativeReflections(*evidence.rirs[i].rsao),
                         context.current.predictions[i].paths});
  }
  return witnesses;
}

// The fit pairs' unexplained reflections, placed.
std::vector<ReflectionPoint> unexplainedPoints(const std::vector<PanelWitness>& witnesses, const AcousticScene& scene,
                                               double speed_of_sound) {
  std::vector<ReflectionPoint> points;
  for (const PanelWitness& w : witnesses) {
    const auto found = unexplainedReflections(w.reflections, w.paths, w.pair, scene, speed_of_sound);
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

// The panel's plane through the reflection point: upright or level, whichever the
// reflection's normal is closer to (walls, screens and partitions; table tops, canopies).
PanelPlane panelPlane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  PanelPlane plane;
  plane.origin = point;
  if (std::abs(normal.z()) > std::sqrt(0.5)) {
    plane.normal = Eigen::Vector3d(0, 0, normal.z() > 0.0 ? 1.0 : -1.0);
    plane.u = Eigen::Vector3d::UnitX();
    plane.v = Eigen::Vector3d::UnitY();
  } else {
    plane.normal = Eigen::Vector3d(normal.x(), normal.y(), 0.0).normalized();
    plane.u = Eigen::Vector3d(-plane.normal.y(), plane.normal.x(), 0.0);
    plane.v = Eigen::Vector3d::UnitZ();
  }
  return plane;
}

// A thin cuboid behind the plane's reflecting face over the extent. An upright panel's own
// x axis is its normal (its yaw), y its width along u; a level one is unrotated.
CuboidObject panelOver(const PanelPlane& plane, const PanelExtent& extent) {
  CuboidObject panel;
  panel.label = "fitted_reflector";
  panel.material = kPanelMaterial;
  panel.center_m = plane.origin + 0.5 * (extent.u_min + extent.u_max) * plane.u +
                   0.5 * (extent.v_min + extent.v_max) * plane.v - 0.5 * kPanelThicknessM * plane.normal;
  if (plane.normal.z() != 0.0) {
    panel.size_m = {extent.width(), extent.height(), kPanelThicknessM};
  } else {
    panel.yaw_rad = std::atan2(plane.normal.y(), plane.normal.x());
    panel.size_m = {kPanelThicknessM, extent.width(), extent.height()};
  }
  return panel;
}

}  // namespace

std::optional<FittedCause> fitMissingReflector(const FitContext& context, std::string& why) {
  const double c = speedOfSoundMPerS(context.evaluator.room().airWith(context.accepted).temperature_c);
  const std::vector<PanelWitness> witnesses = fitWitnesses(context);
  const AcousticScene scene = context.evaluator.room().scene(context.accepted);
  const std::vector<ReflectionPoint> cluster = largestCluster(unexplainedPoints(witnesses, scene, c));
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
  const PanelPlane plane = panelPlane(point, normal);
  std::vector<Eigen::Vector3d> support;
  for (const ReflectionPoint& p : cluster) support.push_back(p.point);
  const PanelBounds bounds = panelBounds(plane, support, witnesses, scene, c);
  const auto make = [&](double side) {
    ModelExtension e;
    e.reflectors.push_back(panelOver(plane, placePanel(bounds, side)));
    return e;
  };
  // The area from the decay terms; 0.5-2.5 m a side in five steps (each one simulation).
  const ScalarFit fit =
      fitScalar([&](double side) { return evaluateWith(context, make(side)); }, 0.5, 2.5, 5, 0, evaluateEachOf(context, make));
  const PanelExtent extent = placePanel(bounds, fit.value);
  const CuboidObject panel = panelOver(plane, extent);
  FittedCause cause;
  cause.cause = "missing_reflector";
  cause.target = "fitted_reflector";
  cause.extension.reflectors.push_back(panel);
  cause.parameters.values = {{"x_m", point.x()}, {"y_m", point.y()}, {"z_m", point.z()},
                             {"normal_x", plane.normal.x()}, {"normal_y", plane.normal.y()}, {"normal_z", plane.normal.z()},
                             {"center_x_m", panel.center_m.x()}, {"center_y_m", panel.center_m.y()},
                             {"center_z_m", panel.center_m.z()}, {"width_m", extent.width()},
                             {"height_m", extent.height()}, {"supporting_reflections", static_cast<double>(cluster.size())}};
  cause.parameters.text["material"] = kPanelMaterial;
  cause.evaluation = fit.evaluation;
  return cause;
}

}  // namespace room_reverb::core
