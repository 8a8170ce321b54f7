#pragma once
// Six degrees of freedom from one measured RIR: the RSAO of the capture point moved to
// another listener position in the same room.
//
// The direct sound comes from the source, placed at the direct sound's distance along its
// direction from the rig. Each early reflection is an image source (imageSourcePosition)
// that does not depend on where the listener stands: for a listener elsewhere its time of
// arrival is the path from the image source, its direction the image source's, its level
// scaled by 1/r. With a room model the image source is matched to the model's image of
// the source in one or two of its planes (the box's faces, the objects' faces): a matched
// reflection keeps the measured path length at the rig and takes the model's direction
// (a single reflection's direction estimate is the least certain part of the RSAO), and
// it is heard only where its image is valid, each reflection point on a face of its plane
// and no leg blocked (the image-source method's test, image_sources.h; where two
// perpendicular planes give the same image, either order of reflection counts). A reflection that
// no plane explains keeps its measured time and direction and fades with the listener's
// distance from the capture point. Without a room model every image source moves
// unchecked, as published extrapolation from one spatial RIR does (Mueller & Zotter
// 2020). The late reverb is a diffuse field and stays as measured, but for the early
// energy of the reflections the model completes, which its fitted onset course gives up.
// The direct sound behind one of the room model's objects is heard around its edge, as
// the simulated route hears it (edge_diffraction.h): later by the detour, from the edge,
// weaker and duller by the edge's loss, which a gain and a one-pole low-pass follow (the
// least-squares fit in dB over the octaves 125 Hz-4 kHz); an object near the line of
// sight weakens it a little.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/acoustics/edge_diffraction.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

class AcousticScene;
struct SpecularPath;

struct ListenerTranslationOptions {
  // As the estimate's (EarlyReflectionOptions::speed_of_sound_m_s).
  double speed_of_sound_m_s = 343.0;
  // Orders of the room model's images a measured reflection may be matched to.
  int max_order = 3;
  // Matching is by time first: a reflection's time of arrival is the RSAO's most certain
  // part (p95 error 0.007 ms on the synthetic rooms, docs/rsao.md), its direction the least
  // (where arrivals overlap, tens of degrees). A model image is a candidate when its path
  // length at the rig is within match_path_m of the measured one (0.12 m: a wall of the
  // room model 5 cm off moves a first-order path by up to 10 cm) and its direction within
  // match_angle_deg of the measured direction; the candidate minimising
  // (path difference / match_path_m)^2 + (angle / match_angle_deg)^2 is taken, one image
  // per reflection, best pairs first.
  double match_path_m = 0.12;
  double match_angle_deg = 30.0;
  // Complete the RSAO from the room model: an image of order 1 to complete_order, valid
  // at the rig but not measured (missed by the estimator: close to another arrival or to
  // the direct sound) and arriving before the mixing time, is added. A second- or higher-
  // order image needs a matched first-order reflection from each of its planes: its level
  // comes from their measured reflection factors (level * distance of each plane's
  // first-order reflection over the direct sound's) and its spectral shape is that of its
  // dullest plane's reflection. A first-order image of a plane with none takes the median
  // measured plane's factor and reflection (the room's typical wall, from the same
  // measurement). Nothing is completed when no plane was measured. 0: no completion.
  int complete_order = 2;
  // An unmatched reflection's gain at distance d from the capture point:
  // exp(-(d / unmatched_fade_m)^2).
  double unmatched_fade_m = 1.0;
};

// Throws InputError naming the bad field.
void validateListenerTranslationOptions(const ListenerTranslationOptions& options);

// What a measured reflection rests on.
enum class ReflectionAnchor {
  kSource,     // the direct sound
  kSurface,    // matched to planes of the room model: moved, heard while its path is valid
  kUnchecked,  // no room model: moved as its measured image source, always heard
  kUnmatched,  // a room model, but no plane explains it: kept, fading with distance
  kModelled,   // not measured: added from the room model's planes (complete_order)
};
const char* anchorName(ReflectionAnchor anchor);

struct AnchoredReflection {
  ReflectionAnchor anchor = ReflectionAnchor::kUnchecked;
  Eigen::Vector3d image_source_m = Eigen::Vector3d::Zero();  // room frame
  double rig_distance_m = 0.0;       // from the image source to the rig
  std::vector<std::size_t> planes;   // kSurface: the scene planes, source side first
  std::string surfaces;              // kSurface: their names, e.g. "wall_x_max, ceiling"
  Eigen::Vector3d model_image_m = Eigen::Vector3d::Zero();  // kSurface: the model's image
  double path_error_m = 0.0;         // kSurface: measured path length minus the model's
  double angle_error_deg = 0.0;      // kSurface: measured direction to the model image's
};

// One reflection of the capture point, as heard at a listener position: `reflection` with
// its time, level, distance and direction moved; `heard` false (and the level 0) where it
// is not heard there.
struct HeardReflection {
  EarlyReflection reflection;
  bool heard = false;
  // The direct sound behind an object: the pole of a one-pole low-pass that gives it the
  // edge's loss rising with frequency (TapTarget::lowpass_pole), its level then the rest
  // of the loss. 0 for every other arrival.
  double lowpass_pole = 0.0;
};

// What moves of one reflection at a listener position: HeardReflection without the
// reflection's own filter, for a renderer that asks every chunk (no allocation per
// reflection). `direction` is a unit vector in the rig's axes.
struct MovedArrival {
  double time_of_arrival_s = 0.0;
  double level = 0.0;  // 0 where not heard
  double distance_m = 0.0;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  bool heard = false;
  double lowpass_pole = 0.0;  // as HeardReflection::lowpass_pole
};

// A reflection heard at a listener position, drawn: `points` run from where the sound
// leaves to the listener (room frame): the source, each reflection point and the listener
// for the direct sound and for reflections on the room model's planes; the image source
// and the listener for reflections no plane checks (unchecked, unmatched).
struct ReflectionPath {
  std::size_t index = 0;  // into anchors() and reflectionsAt()
  ReflectionAnchor anchor = ReflectionAnchor::kUnchecked;
  double level = 0.0;     // the reflection's level there
  std::vector<Eigen::Vector3d> points;
};

class ListenerTranslation {
 public:
  // `measured`: the RSAO at the capture point, reflections[0] the direct sound, each with
  // its distance_m (the estimator sets it). `rig_position_m`, `rig_rotation`: the
  // microphone in the room frame (its axes turned by rig_rotation). `room`: the room
  // model, or none; only its geometry is used. Throws InputError for an RSAO without a
  // direct sound or distances, a rig outside the room model or inside an object, or a
  // source the direct sound places outside it.
  ListenerTranslation(Rsao measured, const Eigen::Vector3d& rig_position_m, const Eigen::Quaterniond& rig_rotation,
                      const std::optional<RoomModel>& room, const ListenerTranslationOptions& options = {});
  ~ListenerTranslation();
  ListenerTranslation(ListenerTranslation&&) noexcept;
  ListenerTranslation& operator=(ListenerTranslation&&) noexcept;

  // The RSAO heard at `listener_m` (room frame), its directions in the rig's axes (the head
  // orientation is the renderer's), reflections sorted by time of arrival after the direct
  // sound; those not heard there are left out. Throws InputError for a non-finite position,
  // one outside the room model or inside an object.
  Rsao at(const Eigen::Vector3d& listener_m) const;
  // Every reflection of anchors() at `listener_m`, in the same order, heard or not (a
  // renderer keeps one tap per reflection and fades those that go); the same checks.
  std::vector<HeardReflection> reflectionsAt(const Eigen::Vector3d& listener_m) const;
  // The same moves alone, into `out` (resized to anchors().size()); the same checks.
  void arrivalsAt(const Eigen::Vector3d& listener_m, std::vector<MovedArrival>& out) const;
  // The paths of the reflections heard at `listener_m` (those reflectionsAt marks heard), for
  // a viewer; the same checks.
  std::vector<ReflectionPath> heardPathsAt(const Eigen::Vector3d& listener_m) const;

  const Eigen::Vector3d& sourcePosition() const { return source_m_; }
  const Eigen::Vector3d& rigPosition() const { return rig_m_; }
  // One per reflection at the rig: the measured ones in the RSAO's order ([0] the direct
  // sound), then those the room model completes (kModelled).
  const std::vector<AnchoredReflection>& anchors() const { return anchors_; }
  // The reflections at the rig, as anchors(): measured, then modelled.
  const std::vector<EarlyReflection>& reflectionsAtRig() const { return reflections_; }
  const Rsao& measured() const { return measured_; }
  // The late reverb played at every position: the measured one, its early course lowered
  // by the energy of the reflections the room model completes (yieldOnsetEnergy).
  const LateReverb& late() const { return late_; }

 private:
  Rsao measured_;
  LateReverb late_;
  Eigen::Vector3d rig_m_;
  Eigen::Quaterniond rig_rotation_;
  ListenerTranslationOptions options_;
  std::unique_ptr<AcousticScene> scene_;  // null without a room model
  Eigen::Vector3d source_m_;
  double time_offset_s_ = 0.0;  // the RSAO's time zero before the emission (0 when it starts at it)
  std::vector<AnchoredReflection> anchors_;
  std::vector<EarlyReflection> reflections_;
  // Per anchor: the orders of its planes that give its image (two perpendicular planes give
  // one image in either order; which is real changes as the listener moves).
  std::vector<std::vector<std::vector<std::size_t>>> plane_orders_;

  void completeFromModel(const std::vector<SpecularPath>& paths, const std::vector<bool>& path_taken,
                         const RoomModel& room);

  // The direct sound at a position among the room model's objects (edge_diffraction.h's
  // directSoundPastObjects): heard or blocked, the edge's loss as a gain and a one-pole
  // low-pass, and the edge's way round where it arrives bent.
  struct DirectSoundAt {
    bool heard = true;
    double gain = 1.0;
    double lowpass_pole = 0.0;
    std::optional<EdgeDetour> bent;
  };
  DirectSoundAt directSoundAt(const Eigen::Vector3d& listener_m) const;
  // That gain at the rig, which the measured direct sound's level already holds.
  double rig_direct_gain_ = 1.0;
};

}  // namespace room_reverb::core
