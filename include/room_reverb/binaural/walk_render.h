#pragma once
// A listener walking through a measured room, rendered offline: the binaural_renderer
// node's stream (the RSAO's late part convolved, its direct sound and early reflections
// as taps moved to the listener every block, the head turned by the pose), run on a file
// of poses instead of live topics, so that a walk can be heard, compared and repeated.
//
// Pose file (CSV): a header `t_s,x_m,y_m,z_m,qx,qy,qz,qw`, then one row per pose: time [s,
// increasing], position [m, room frame], orientation (a quaternion, normalised on
// reading). Between rows the position moves linearly and the orientation by slerp; before
// the first row and after the last the pose holds.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "room_reverb/acoustics/simulated_walk.h"
#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/binaural/reflection_tap_bank.h"
#include "room_reverb/rsao/listener_translation.h"

namespace room_reverb::core {

struct ListenerPose {
  double t_s = 0.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

// InputError naming the line for a missing or wrong header, a row without eight numbers,
// a non-finite value, a quaternion of zero length, times that do not increase, or no row.
std::vector<ListenerPose> parsePoseCsv(const std::string& text);
std::vector<ListenerPose> loadPoseCsv(const std::string& path);

// The pose at `t_s` (see above). `poses` must not be empty.
ListenerPose poseAt(const std::vector<ListenerPose>& poses, double t_s);

// The taps' targets for a listener at `listener_m`: every reflection of `translation`,
// silent where it is not heard there. Throws InputError as ListenerTranslation::at does.
std::vector<TapTarget> tapTargetsAt(const ListenerTranslation& translation, const Eigen::Vector3d& listener_m);

// The targets a fraction `u` (0..1) of the way from `from` to `to`, the same reflections in
// the same order, into `out` (reused: no allocation once it has the size): delay and level
// linearly, the direction along the arc between the two (normalised blend; `to`'s where
// the two are opposite). A pose per chunk with the targets blended per block costs one
// ListenerTranslation::reflectionsAt a chunk; over a chunk's 10.7 ms a walker moves about
// a centimetre, along which delay and level are linear to well under a sample and 0.01 dB.
// `to` alone where the two differ in size.
void tapTargetsBetween(const std::vector<TapTarget>& from, const std::vector<TapTarget>& to, double u,
                       std::vector<TapTarget>& out);

// A walking listener's tap targets as a live renderer plays them: found once a chunk, where
// the listener is at the chunk's end, and blended block by block from where the last chunk
// left them (tapTargetsBetween). The ROS renderer and its benchmark both play it.
class ChunkedTapTargets {
 public:
  // The taps stand at `targets`, with no blend (a new room; empty: nothing to blend from).
  void place(std::vector<TapTarget> targets);
  // A chunk of `blocks` blocks (at least 1) that ends at `targets`.
  void beginChunk(std::vector<TapTarget> targets, std::size_t blocks);
  // The targets at the end of block `b` (0-based) of the chunk; no allocation once sized.
  const std::vector<TapTarget>& atBlock(std::size_t b);
  // The chunk's end becomes the next chunk's start.
  void endChunk();

 private:
  std::vector<TapTarget> from_, to_, now_;
  std::size_t blocks_ = 1;
};

// `dry`: mono at 48 kHz. The output (left, right, 48 kHz) is the dry sound's length plus
// the late part's. Throws InputError for a listener position the translation refuses.
AudioBuffer renderWalk(const AudioBuffer& dry, const ListenerTranslation& translation, const BinauralDecoder& decoder,
                       const std::vector<ListenerPose>& poses, std::uint32_t seed = 1);

// The simulated route walked: the walk's late part convolved, its image-source part
// computed at the listener's position every `update_blocks` blocks of 256 frames and
// crossfaded in (BinauralStream::setEarlyResponse), the head turned by the pose. `dry`:
// mono at 48 kHz; the output is its length plus the late part's. Every pose is checked
// first (InputError as SimulatedWalk::earlyAt).
AudioBuffer renderSimulatedWalk(const AudioBuffer& dry, const SimulatedWalk& walk, const BinauralDecoder& decoder,
                                const std::vector<ListenerPose>& poses, std::size_t update_blocks = 2);

}  // namespace room_reverb::core
