// missing_reflector: a strong early reflection in a measured B-format RIR that no specular
// path of the model explains is taken as a surface the model lacks. Its time of arrival
// (after the direct sound) and direction place the reflection point by image-source
// geometry: the point P on the arrival ray from the receiver R with |S - P| + |P - R| equal
// to the reflection's path length L, that is
//   P = R + d u,  d = (L^2 - |S - R|^2) / (2 (L - u . (S - R))),
// and the reflecting face is normal to the bisector of the directions from P to S and R.
// Points found at several fit pairs are clustered; the panel (a thin cuboid, upright or
// level, whichever the normal is closer to) goes where most agree, and its size is fitted.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "cause_fitting.h"
#include "room_reverb/acoustics/propagation.h"
#include "room_reverb/common/directions.h"
#include "room_reverb/evaluation/reflection_matching.h"

namespace room_reverb::core {
namespace {

constexpr double kMatchTimeS = 0.0006;       // a specular path within 0.6 ms ...
constexpr double kMatchAngleRad = 0.55;      // ... and 30 degrees explains a reflection
constexpr double kStrongLevelDb = -14.0;     // re the direct sound: weaker ones are not chased
constexpr double kLatestDelayS = 0.030;      // after this, reflections crowd too densely
constexpr double kClusterRadiusM = 0.6;
// A reflection point this close to the model's own surfaces, or outside the room, is a
// surface the model has (its reflection mistimed or of a higher order than the model's
// image sources), not a missing one.
constexpr double kWallClearanceM = 0.3;
constexpr double kPanelThicknessM = 0.04;
constexpr const char* kPanelMaterial = "wood_panel";
constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

struct ReflectionPoint {
  Eigen::Vector3d point, normal;
  double level_db = 0.0;
};

bool explained(const std::vector<SpecularPath>& paths, double delay_s, const Eigen::Vector3d& arrival) {
  if (paths.empty()) return false;
  const double direct = paths.front().delay_s;
  for (const SpecularPath& p : paths) {
    if (p.order == 0) continue;
    if (std::abs((p.delay_s - direct) - delay_s) > kMatchTimeS) continue;
    if (std::acos(std::clamp(p.arrival_direction.dot(arrival), -1.0, 1.0)) <= kMatchAngleRad) return true;
  }
  return false;
}

std::vector<ReflectionPoint> unexplainedPoints(const FitContext& context, double speed_of_sound) {
  const MeasuredEvidence& evidence = context.evaluator.evidence();
  const AcousticScene scene = context.evaluator.room().scene(context.accepted);
  std::vector<ReflectionPoint> points;
  const bool split = evidence.rirs.size() >= 2;
  for (std::size_t i = 0; i < evidence.rirs.size(); ++i) {
    if (split && i % 2 == 1) continue;  // held-out pairs do not place the panel
    const auto& rsao = evidence.rirs[i].rsao;
    if (!rsao || rsao->reflections.size() < 2 || i >= context.current.predictions.size()) continue;
    const auto& paths = context.current.predictions[i].paths;
    const Eigen::Vector3d S = evidence.rirs[i].pair.source_m, R = evidence.rirs[i].pair.receiver_m;
    const double direct_length = (S - R).norm();
    for (const RelativeReflection& r : relativeReflections(*rsao)) {
      const double delay = r.delay_s, level_db = r.level_db;
      if (delay <= 0.0 || delay > kLatestDelayS || level_db < kStrongLevelDb) continue;
      const Eigen::Vector3d u = unitVectorFromAngles(r.azimuth_deg * kRadiansPerDegree, r.elevation_deg * kRadiansPerDegree);
      if (explained(paths, delay, u)) continue;
      const double L = direct_length + speed_of_sound * delay;
      const double denominator = 2.0 * (L - u.dot(S - R));
      if (denominator <= 1e-6) continue;
      const double d = (L * L - direct_length * direct_length) / denominator;
      const Eigen::Vector3d P = R + d * u;
      if (!P.allFinite() || !scene.isInside(P) || scene.distanceToNearestSurface(P) < kWallClearanceM) continue;
      const Eigen::Vector3d n = ((S - P).normalized() + (R - P).normalized()).normalized();
      points.push_back({P, n, level_db});
    }
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
