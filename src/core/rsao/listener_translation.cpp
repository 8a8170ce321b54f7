#include "room_reverb/rsao/listener_translation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/edge_diffraction.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/acoustics/room_shape.h"
#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/lpc.h"
#include "room_reverb/rsao/onset_ramp_fit.h"
#include "room_reverb/rsao/reflection_tap.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Below this an unmatched reflection is left out (-60 dB).
constexpr double kInaudibleGain = 1e-3;

std::string formatPoint(const Eigen::Vector3d& p) {
  std::ostringstream os;
  os.precision(3);
  os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ") m";
  return os.str();
}

// The edge's octave gains over 125 Hz-4 kHz (bands 1-6) as a gain and a one-pole low-pass
// y[n] = (1 - p) x[n] + p y[n-1] (the tap's filters are its reflection's, so the loss is
// added after them): the pole whose response, in dB, fits theirs best in least squares
// with the gain free, and the gain that then keeps their power over those bands. Gains
// alike in every band (no object near, or one far on the lit side) need no pole.
struct EdgeLossFit {
  double gain = 1.0;
  double pole = 0.0;
};
EdgeLossFit fitEdgeLoss(const OctaveBandValues& gains) {
  constexpr int kFirst = 1, kLast = 6, kCount = kLast - kFirst + 1;
  static const std::array<double, kCount> cosines = [] {
    const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
    std::array<double, kCount> c{};
    for (int b = kFirst; b <= kLast; ++b) {
      c[static_cast<std::size_t>(b - kFirst)] =
          std::cos(2.0 * kPi * bands[static_cast<std::size_t>(b)].center_hz / kInternalSampleRateHz);
    }
    return c;
  }();
  // The one-pole's power response in band b, and in dB.
  const auto response = [&](double p, std::size_t b) { return (1.0 - p) * (1.0 - p) / (1.0 - 2.0 * p * cosines[b] + p * p); };
  double target_power = 0.0, lowest_db = 1e9, highest_db = -1e9;
  std::array<double, kCount> target_db{};
  for (int b = kFirst; b <= kLast; ++b) {
    const double g = gains[static_cast<std::size_t>(b)];
    target_power += g * g;
    const double db = 20.0 * std::log10(std::max(g, 1e-6));
    target_db[static_cast<std::size_t>(b - kFirst)] = db;
    lowest_db = std::min(lowest_db, db);
    highest_db = std::max(highest_db, db);
  }
  EdgeLossFit fit;
  if (highest_db - lowest_db > 0.01) {
    const auto residual = [&](double p) {
      std::array<double, kCount> error{};
      double mean = 0.0;
      for (std::size_t b = 0; b < kCount; ++b) {
        error[b] = target_db[b] - 10.0 * std::log10(response(p, b));
        mean += error[b] / kCount;
      }
      double sum = 0.0;
      for (double e : error) sum += (e - mean) * (e - mean);
      return sum;
    };
    // Golden-section search over [0, 0.98]: the residual has one minimum there (each
    // band's response falls monotonically with p, the high bands' faster).
    const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
    double lo = 0.0, hi = 0.98;
    double x1 = hi - ratio * (hi - lo), x2 = lo + ratio * (hi - lo);
    double f1 = residual(x1), f2 = residual(x2);
    for (int k = 0; k < 24; ++k) {
      if (f1 < f2) {
        hi = x2, x2 = x1, f2 = f1, x1 = hi - ratio * (hi - lo), f1 = residual(x1);
      } else {
        lo = x1, x1 = x2, f1 = f2, x2 = lo + ratio * (hi - lo), f2 = residual(x2);
      }
    }
    fit.pole = residual(0.0) <= std::min(f1, f2) ? 0.0 : 0.5 * (lo + hi);
  }
  double response_power = 0.0;
  for (std::size_t b = 0; b < kCount; ++b) response_power += response(fit.pole, b);
  fit.gain = std::sqrt(target_power / response_power);
  return fit;
}

void setDirection(EarlyReflection& r, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d u = direction.normalized();
  r.azimuth_rad = std::atan2(u.y(), u.x());
  r.elevation_rad = std::asin(std::clamp(u.z(), -1.0, 1.0));
}

// Only the geometry of the room model matters here: every material it names becomes a
// placeholder, so that a model whose materials the library lacks still moves a listener.
AcousticScene geometryScene(const RoomModel& model) {
  TriangleMesh mesh = roomModelToMesh(model);
  MaterialLibrary placeholders;
  for (const std::string& name : mesh.material_names) {
    AcousticMaterial m;
    m.name = name;
    m.source = "placeholder: geometry only";
    placeholders.add(m);
  }
  RoomShape shape;
  shape.size_m = model.size_m;
  shape.has_ceiling = model.has_ceiling;
  shape.objects = model.objects;
  return AcousticScene(std::move(mesh), placeholders, {}, std::move(shape));
}

void requireFreeAir(const AcousticScene& scene, const Eigen::Vector3d& p, const std::string& what,
                    const std::vector<CuboidObject>& objects) {
  if (!p.allFinite()) throw InputError(what + " position is not finite");
  const RoomShape* shape = scene.roomShape();
  if (!shape->inBox(p)) throw InputError(what + " " + formatPoint(p) + " is outside the room model's box");
  if (const auto object = shape->objectContaining(p)) {
    throw InputError(what + " " + formatPoint(p) + " is inside object " + std::to_string(*object) + " (" +
                     objects[*object].label + ") of the room model");
  }
}

// A plane's name: the box face it lies in, or the object whose face it is.
std::string planeName(const AcousticScene& scene, std::size_t plane_index, const RoomModel& model) {
  const ScenePlane& plane = scene.planes()[plane_index];
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(std::abs(plane.normal[axis]) - 1.0) > 1e-6) continue;
    const double at = plane.offset * plane.normal[axis];  // the coordinate the plane lies at
    if (std::abs(at) < 1e-6) return kRoomSurfaceNames[axis == 2 ? 0 : 2 + 2 * axis];
    if (std::abs(at - model.size_m[axis]) < 1e-6) return kRoomSurfaceNames[axis == 2 ? 1 : 3 + 2 * axis];
  }
  const TriangleMesh& mesh = scene.mesh();
  const auto& t = mesh.triangles[plane.triangles.front()];
  const Eigen::Vector3d centroid = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
  for (std::size_t i = 0; i < model.objects.size(); ++i) {
    if (distanceToCuboid(model.objects[i], centroid) < 1e-6) {
      return "object " + std::to_string(i) + " (" + model.objects[i].label + ")";
    }
  }
  return "plane " + std::to_string(plane_index);
}

// The source mirrored in `planes`, source side first.
Eigen::Vector3d imageIn(const AcousticScene& scene, const Eigen::Vector3d& source, const std::vector<std::size_t>& planes) {
  Eigen::Vector3d image = source;
  for (std::size_t p : planes) {
    const ScenePlane& plane = scene.planes()[p];
    image -= 2.0 * (plane.normal.dot(image) - plane.offset) * plane.normal;
  }
  return image;
}

std::vector<std::size_t> planesOf(const AcousticScene& scene, const SpecularPath& path) {
  std::vector<std::size_t> planes;
  for (std::size_t t : path.triangles) planes.push_back(scene.planeOf(t));
  return planes;
}

}  // namespace

void validateListenerTranslationOptions(const ListenerTranslationOptions& o) {
  if (!(o.speed_of_sound_m_s > 0.0) || !std::isfinite(o.speed_of_sound_m_s)) {
    throw InputError("speed_of_sound_m_s must be a positive speed, e.g. 343");
  }
  if (o.max_order < 1 || o.max_order > 4) throw InputError("max_order must be 1 to 4");
  if (o.complete_order < 0 || o.complete_order > o.max_order) {
    throw InputError("complete_order must be 0 to max_order (" + std::to_string(o.max_order) + ")");
  }
  if (!(o.match_path_m > 0.0) || !std::isfinite(o.match_path_m)) throw InputError("match_path_m must be positive");
  if (!(o.match_angle_deg > 0.0) || !(o.match_angle_deg <= 180.0)) {
    throw InputError("match_angle_deg must be in (0, 180]");
  }
  if (!(o.unmatched_fade_m > 0.0) || !std::isfinite(o.unmatched_fade_m)) {
    throw InputError("unmatched_fade_m must be a positive distance in m");
  }
}

const char* anchorName(ReflectionAnchor anchor) {
  switch (anchor) {
    case ReflectionAnchor::kSource: return "source";
    case ReflectionAnchor::kSurface: return "surface";
    case ReflectionAnchor::kUnchecked: return "unchecked";
    case ReflectionAnchor::kUnmatched: return "unmatched";
    case ReflectionAnchor::kModelled: return "modelled";
  }
  return "?";
}

ListenerTranslation::~ListenerTranslation() = default;
ListenerTranslation::ListenerTranslation(ListenerTranslation&&) noexcept = default;
ListenerTranslation& ListenerTranslation::operator=(ListenerTranslation&&) noexcept = default;

ListenerTranslation::ListenerTranslation(Rsao measured, const Eigen::Vector3d& rig_position_m,
                                         const Eigen::Quaterniond& rig_rotation, const std::optional<RoomModel>& room,
                                         const ListenerTranslationOptions& options)
    : measured_(std::move(measured)), late_(measured_.late), rig_m_(rig_position_m), rig_rotation_(rig_rotation.normalized()),
      options_(options) {
  validateListenerTranslationOptions(options_);
  if (measured_.reflections.empty()) throw InputError("the RSAO has no direct sound to place the source by");
  for (const EarlyReflection& r : measured_.reflections) {
    if (!(r.distance_m > 0.0) || !std::isfinite(r.distance_m)) {
      throw InputError("an RSAO reflection has no image-source distance (distance_m); estimate it again, or give "
                       "the source's distance");
    }
  }
  if (!rig_m_.allFinite()) throw InputError("the rig position is not finite");
  if (!rig_rotation.coeffs().allFinite() || rig_rotation.norm() < 1e-6) throw InputError("the rig rotation is not a rotation");

  const double c = options_.speed_of_sound_m_s;
  const EarlyReflection& direct = measured_.reflections.front();
  source_m_ = rig_m_ + rig_rotation_ * (direct.distance_m * reflectionDirection(direct));
  time_offset_s_ = direct.time_of_arrival_s - direct.distance_m / c;

  reflections_ = measured_.reflections;
  anchors_.resize(measured_.reflections.size());
  for (std::size_t k = 0; k < measured_.reflections.size(); ++k) {
    const EarlyReflection& r = measured_.reflections[k];
    AnchoredReflection& a = anchors_[k];
    a.anchor = k == 0 ? ReflectionAnchor::kSource : ReflectionAnchor::kUnchecked;
    a.image_source_m = rig_m_ + rig_rotation_ * (r.distance_m * reflectionDirection(r));
    a.rig_distance_m = r.distance_m;
  }
  if (!room) return;

  scene_ = std::make_unique<AcousticScene>(geometryScene(*room));
  requireFreeAir(*scene_, rig_m_, "the rig", room->objects);
  try {
    requireFreeAir(*scene_, source_m_, "the source", room->objects);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + ", where the direct sound's distance (" +
                     std::to_string(direct.distance_m) + " m) and direction place it; check the rig position and "
                     "the source distance");
  }

  // The measured direct sound holds whatever an object near its way took from it there.
  const DirectSoundAt at_rig = directSoundAt(rig_m_);
  if (at_rig.heard && at_rig.gain > 0.0) rig_direct_gain_ = at_rig.gain;

  // Every image of the source up to max_order valid at the rig, matched one to one to the
  // measured reflections, by path length first and direction second (the options).
  ImageSourceOptions search;
  search.max_order = options_.max_order;
  const std::vector<SpecularPath> paths = computeImageSources(*scene_, source_m_, rig_m_, PropagationModel{}, search);
  struct Candidate {
    double cost;
    std::size_t reflection, path;
    double path_error_m, angle_deg;
  };
  std::vector<Candidate> candidates;
  for (std::size_t k = 1; k < anchors_.size(); ++k) {
    const Eigen::Vector3d measured_direction = anchors_[k].image_source_m - rig_m_;
    for (std::size_t p = 0; p < paths.size(); ++p) {
      if (paths[p].order == 0) continue;
      const Eigen::Vector3d model_path = paths[p].image_position - rig_m_;
      const double path_error = anchors_[k].rig_distance_m - model_path.norm();
      const double angle = std::acos(std::clamp(model_path.normalized().dot(measured_direction.normalized()), -1.0, 1.0)) *
                           180.0 / 3.14159265358979323846;
      if (std::abs(path_error) > options_.match_path_m || angle > options_.match_angle_deg) continue;
      const double cost = std::pow(path_error / options_.match_path_m, 2) + std::pow(angle / options_.match_angle_deg, 2);
      candidates.push_back({cost, k, p, path_error, angle});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) { return x.cost < y.cost; });
  std::vector<bool> path_taken(paths.size(), false);
  for (std::size_t k = 1; k < anchors_.size(); ++k) anchors_[k].anchor = ReflectionAnchor::kUnmatched;
  for (const Candidate& m : candidates) {
    AnchoredReflection& a = anchors_[m.reflection];
    if (a.anchor == ReflectionAnchor::kSurface || path_taken[m.path]) continue;
    path_taken[m.path] = true;
    a.anchor = ReflectionAnchor::kSurface;
    a.model_image_m = paths[m.path].image_position;
    a.path_error_m = m.path_error_m;
    a.angle_error_deg = m.angle_deg;
    a.planes = planesOf(*scene_, paths[m.path]);
    // The measured path length (a time, exact to a few microseconds) along the model's
    // direction.
    a.image_source_m = rig_m_ + a.rig_distance_m * (a.model_image_m - rig_m_).normalized();
    for (std::size_t i = 0; i < a.planes.size(); ++i) {
      a.surfaces += (i ? ", " : "") + planeName(*scene_, a.planes[i], *room);
    }
  }
  completeFromModel(paths, path_taken, *room);
  plane_orders_.resize(anchors_.size());
  for (std::size_t k = 0; k < anchors_.size(); ++k) {
    if (anchors_[k].planes.empty()) continue;
    std::vector<std::size_t> order = anchors_[k].planes;
    std::sort(order.begin(), order.end());
    do {
      if ((imageIn(*scene_, source_m_, order) - anchors_[k].model_image_m).norm() < 1e-6) plane_orders_[k].push_back(order);
    } while (std::next_permutation(order.begin(), order.end()));
  }
}

void ListenerTranslation::completeFromModel(const std::vector<SpecularPath>& paths, const std::vector<bool>& path_taken,
                                            const RoomModel& room) {
  if (options_.complete_order < 1) return;
  // Each plane with a matched first-order reflection: its pressure reflection factor as
  // measured (the reflection's level times its path length over the direct sound's), and
  // that reflection.
  struct MeasuredPlane {
    double factor;
    std::size_t reflection;
  };
  std::map<std::size_t, MeasuredPlane> measured_planes;
  const double direct_reach = reflections_[0].level * anchors_[0].rig_distance_m;
  if (!(direct_reach > 0.0)) return;
  for (std::size_t k = 1; k < anchors_.size(); ++k) {
    if (anchors_[k].anchor != ReflectionAnchor::kSurface || anchors_[k].planes.size() != 1) continue;
    measured_planes[anchors_[k].planes[0]] = {reflections_[k].level * anchors_[k].rig_distance_m / direct_reach, k};
  }
  if (measured_planes.empty()) return;
  // A plane whose first-order reflection the estimator missed (close to the direct sound
  // or to another arrival) takes the median of the measured planes' factors, and the
  // spectrum of that plane's reflection: the room's typical wall, from the same
  // measurement.
  std::vector<const MeasuredPlane*> by_factor;
  for (const auto& [plane, m] : measured_planes) by_factor.push_back(&m);
  std::sort(by_factor.begin(), by_factor.end(), [](const MeasuredPlane* a, const MeasuredPlane* b) { return a->factor < b->factor; });
  const MeasuredPlane typical = *by_factor[by_factor.size() / 2];
  const double c = options_.speed_of_sound_m_s;
  const double end_s = measured_.late.mixing_time_s > 0.0 ? measured_.late.mixing_time_s : 0.0;
  for (std::size_t p = 0; p < paths.size(); ++p) {
    const SpecularPath& path = paths[p];
    if (path_taken[p] || path.order < 1 || path.order > options_.complete_order) continue;
    const double distance = (path.image_position - rig_m_).norm();
    const double time = time_offset_s_ + distance / c;
    if (end_s > 0.0 && time >= end_s) continue;
    const std::vector<std::size_t> planes = planesOf(*scene_, path);
    double factor = 1.0;
    const MeasuredPlane* dullest = nullptr;
    for (std::size_t plane : planes) {
      const auto it = measured_planes.find(plane);
      // Only a first-order reflection takes the typical wall: a higher order needs each of
      // its planes measured.
      const MeasuredPlane* m = it != measured_planes.end() ? &it->second : (path.order == 1 ? &typical : nullptr);
      if (!m) {
        dullest = nullptr;
        break;
      }
      factor *= m->factor;
      if (!dullest || m->factor < dullest->factor) dullest = m;
    }
    if (!dullest) continue;
    EarlyReflection r = reflections_[dullest->reflection];
    r.time_of_arrival_s = time;
    r.level = factor * direct_reach / distance;
    r.distance_m = distance;
    r.confidence.reset();
    setDirection(r, rig_rotation_.conjugate() * (path.image_position - rig_m_));
    AnchoredReflection a;
    a.anchor = ReflectionAnchor::kModelled;
    a.image_source_m = path.image_position;
    a.model_image_m = path.image_position;
    a.rig_distance_m = distance;
    a.planes = planes;
    for (std::size_t i = 0; i < planes.size(); ++i) a.surfaces += (i ? ", " : "") + planeName(*scene_, planes[i], room);
    anchors_.push_back(std::move(a));
    reflections_.push_back(std::move(r));
  }
  // The completed reflections' early energy is in the late part's fitted course already
  // (it was fitted to the measured early energy, theirs included): the course gives it up,
  // and where it holds less than they bring, their levels come down to what it holds.
  const auto first_modelled = reflections_.begin() + static_cast<std::ptrdiff_t>(measured_.reflections.size());
  std::vector<EarlyReflection> modelled(first_modelled, reflections_.end());
  Rsao yielding = measured_;
  yieldOnsetEnergy(modelled, yielding);
  std::copy(modelled.begin(), modelled.end(), first_modelled);
  late_ = yielding.late;
}

ListenerTranslation::DirectSoundAt ListenerTranslation::directSoundAt(const Eigen::Vector3d& listener_m) const {
  if (!scene_ || !scene_->roomShape() || scene_->roomShape()->objects.empty()) return {};
  const std::vector<CuboidObject>& objects = scene_->roomShape()->objects;
  const bool in_view = std::none_of(objects.begin(), objects.end(), [&](const CuboidObject& object) {
    return segmentCrossesCuboid(object, source_m_, listener_m);
  });
  const std::optional<DirectSoundPast> past =
      directSoundPastObjects(objects, source_m_, listener_m, in_view, options_.speed_of_sound_m_s);
  if (!past) return {false, 0.0, 0.0, std::nullopt};
  const EdgeLossFit fit = fitEdgeLoss(past->gains);
  return {true, fit.gain, fit.pole, past->bent ? past->detour : std::nullopt};
}

void ListenerTranslation::arrivalsAt(const Eigen::Vector3d& listener_m, std::vector<MovedArrival>& out) const {
  if (!listener_m.allFinite()) throw InputError("the listener position is not finite");
  if (scene_) requireFreeAir(*scene_, listener_m, "the listener", scene_->roomShape()->objects);
  const double c = options_.speed_of_sound_m_s;
  const Eigen::Quaterniond to_rig = rig_rotation_.conjugate();
  const double moved_m = (listener_m - rig_m_).norm();
  out.resize(anchors_.size());
  for (std::size_t k = 0; k < anchors_.size(); ++k) {
    const AnchoredReflection& a = anchors_[k];
    const EarlyReflection& r = reflections_[k];
    MovedArrival& h = out[k];
    h.time_of_arrival_s = r.time_of_arrival_s;
    h.level = r.level;
    h.distance_m = r.distance_m;
    h.direction = reflectionDirection(r);
    h.lowpass_pole = 0.0;
    if (a.anchor == ReflectionAnchor::kUnmatched) {
      const double gain = std::exp(-std::pow(moved_m / options_.unmatched_fade_m, 2));
      h.heard = gain >= kInaudibleGain;
      h.level *= h.heard ? gain : 0.0;
      continue;
    }
    const Eigen::Vector3d path = a.image_source_m - listener_m;
    const double distance = std::max(path.norm(), 0.01);
    h.time_of_arrival_s = time_offset_s_ + distance / c;
    h.level *= a.rig_distance_m / distance;
    h.distance_m = distance;
    h.direction = (to_rig * path).normalized();
    h.heard = true;
    if (a.anchor == ReflectionAnchor::kSource) {
      const DirectSoundAt direct = directSoundAt(listener_m);
      if (direct.bent) {
        // Around the edge: the detour's length, from the edge's last turn.
        h.time_of_arrival_s = time_offset_s_ + direct.bent->length_m / c;
        h.level = r.level * a.rig_distance_m / direct.bent->length_m;
        h.distance_m = direct.bent->length_m;
        h.direction = (to_rig * (direct.bent->turns.back() - listener_m)).normalized();
      }
      h.heard = direct.heard;
      h.level *= direct.heard ? direct.gain / rig_direct_gain_ : 0.0;
      h.lowpass_pole = direct.heard ? direct.lowpass_pole : 0.0;
    }
    if (a.anchor == ReflectionAnchor::kSurface || a.anchor == ReflectionAnchor::kModelled) {
      // Heard while the model has a valid path to its image: each reflection point on a
      // face of its plane, no leg blocked.
      h.heard = std::any_of(plane_orders_[k].begin(), plane_orders_[k].end(), [&](const std::vector<std::size_t>& planes) {
        return specularPathValid(*scene_, source_m_, listener_m, planes);
      });
      if (!h.heard) h.level = 0.0;
    }
  }
  // An unmatched reflection keeps its time: where the listener has moved away from the
  // source, one that would now arrive with or before the direct sound is not heard.
  const double direct_s = out.front().time_of_arrival_s;
  for (std::size_t k = 1; k < out.size(); ++k) {
    if (out[k].heard && out[k].time_of_arrival_s <= direct_s) {
      out[k].heard = false;
      out[k].level = 0.0;
    }
  }
}

std::vector<HeardReflection> ListenerTranslation::reflectionsAt(const Eigen::Vector3d& listener_m) const {
  std::vector<MovedArrival> arrivals;
  arrivalsAt(listener_m, arrivals);
  std::vector<HeardReflection> out(arrivals.size());
  for (std::size_t k = 0; k < arrivals.size(); ++k) {
    const MovedArrival& m = arrivals[k];
    HeardReflection& h = out[k];
    h.reflection = reflections_[k];
    h.reflection.time_of_arrival_s = m.time_of_arrival_s;
    h.reflection.level = m.level;
    h.reflection.distance_m = m.distance_m;
    // An unmatched reflection keeps its measured angles exactly.
    if (anchors_[k].anchor != ReflectionAnchor::kUnmatched) setDirection(h.reflection, m.direction);
    h.heard = m.heard;
    h.lowpass_pole = m.lowpass_pole;
  }
  return out;
}

std::vector<ReflectionPath> ListenerTranslation::heardPathsAt(const Eigen::Vector3d& listener_m) const {
  const std::vector<HeardReflection> heard = reflectionsAt(listener_m);
  std::vector<ReflectionPath> paths;
  for (std::size_t k = 0; k < heard.size(); ++k) {
    if (!heard[k].heard) continue;
    ReflectionPath path;
    path.index = k;
    path.anchor = anchors_[k].anchor;
    path.level = heard[k].reflection.level;
    if (path.anchor == ReflectionAnchor::kSurface || path.anchor == ReflectionAnchor::kModelled) {
      for (const std::vector<std::size_t>& planes : plane_orders_[k]) {
        if (auto points = specularReflectionPoints(*scene_, source_m_, listener_m, planes)) {
          path.points.push_back(source_m_);
          path.points.insert(path.points.end(), points->begin(), points->end());
          break;
        }
      }
    } else if (path.anchor == ReflectionAnchor::kSource) {
      path.points.push_back(source_m_);
      const DirectSoundAt direct = directSoundAt(listener_m);
      if (direct.bent) path.points.insert(path.points.end(), direct.bent->turns.begin(), direct.bent->turns.end());
    } else {
      path.points.push_back(anchors_[k].image_source_m);
    }
    path.points.push_back(listener_m);
    paths.push_back(std::move(path));
  }
  return paths;
}

Rsao ListenerTranslation::at(const Eigen::Vector3d& listener_m) const {
  Rsao out = measured_;
  out.late = late_;
  out.reflections.clear();
  for (HeardReflection& h : reflectionsAt(listener_m)) {
    if (h.lowpass_pole > 0.0) {
      // The low-pass joins the reflection's own sections, as the taps run it after them.
      EarlyReflection& r = h.reflection;
      if (r.sos.empty() && r.lpc.size() > 1) r.sos = allPoleToSections(r.lpc, r.lpc_gain);
      r.sos.push_back(BiquadSection{1.0 - h.lowpass_pole, 0.0, 0.0, -h.lowpass_pole, 0.0});
    }
    if (h.heard || out.reflections.empty()) out.reflections.push_back(std::move(h.reflection));
  }
  std::sort(out.reflections.begin() + 1, out.reflections.end(),
            [](const EarlyReflection& x, const EarlyReflection& y) { return x.time_of_arrival_s < y.time_of_arrival_s; });
  return out;
}

}  // namespace room_reverb::core
