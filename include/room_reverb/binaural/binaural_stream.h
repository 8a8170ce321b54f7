#pragma once
// Real-time, head-tracked binaural rendering of a mono source in a room, block by block:
//
//   source --(room: 1 -> K ambisonic RIR, partitioned convolution)--> K-channel field
//          --(head tracking: K x K rotation, interpolated across each block)-->
//          --(binaural decoder: K -> 2 short FIRs)--> left, right
//
// K = (N+1)^2 for the decoder's order N. A room of lower order is zero-padded: its missing
// channels are single-zero filters, which the convolver skips (a 2 s first-order room in
// a third-order stream costs 0.007 of a core per 10.7 ms chunk, a third-order one 0.016;
// bench_binaural_renderer, docs/six_dof.md). Changing the room
// crossfades inside the room convolver over `crossfade_blocks`, with the input history
// kept, so the old room's tail rings on and the new one starts complete: no click, no gap.
// The head rotation is interpolated linearly, sample by sample, from the previous block's
// matrix to the new one, so a head turn does not step either.
//
// Timing: no algorithmic delay beyond the block (frame j of the k-th output block is
// y[kB + j]); see partitioned_convolver.h for what "one block of latency" means.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/audio/partitioned_convolver.h"
#include "room_reverb/binaural/binaural_decoder.h"
#include "room_reverb/binaural/reflection_tap_bank.h"

namespace room_reverb::core {

struct BinauralStreamOptions {
  std::size_t block_size = PartitionedConvolver::kDefaultBlockSize;  // frames at 48 kHz
  std::size_t crossfade_blocks = 4;  // room changes fade over this many blocks (21 ms at 256)
  double max_response_s = 4.0;       // longer room responses are truncated, with a warning
  // setEarlyResponse's changes fade over this many blocks (a walking listener's early
  // part changes every few blocks).
  std::size_t early_crossfade_blocks = 2;
  // A mixed-order room (late_order.h): the room response's orders above 1 end after
  // full_order_s, orders 0-1 diffuse-field equalised after it; a 2 s third-order room then
  // costs about two thirds as much (docs/rendering.md). Off: every order throughout.
  bool mixed_order_late = false;
  double full_order_s = 0.1;  // s after the response's start, with mixed_order_late
};

// The room response (AmbiX at 48 kHz, of the decoder's order or below) as a stream with
// `options` plays it: cut to a mixed-order room (late_order.h) when mixed_order_late is
// set and the response is of order 2 or 3, unchanged otherwise. For renderings that must
// sound as the stream does (the node's ~render_to_file). Throws InputError as
// reduceLateOrder does.
AudioBuffer roomResponseAsStreamed(const AudioBuffer& ambix, const BinauralDecoder& decoder,
                                   const BinauralStreamOptions& options);

// A response transformed for one stream's room or early convolver (prepareRoom,
// prepareEarlyResponse): the FFTs of its partitions, which are most of the cost of a room
// change, done on any thread so that the audio thread only swaps the response in.
struct PreparedResponse {
  std::shared_ptr<const PreparedFilters> filters;
  std::string warning;  // truncation to max_response_s ("" when none)
  bool empty = false;   // an empty early response: setEarlyResponse removes the early part
};

class BinauralStream {
 public:
  // The early convolver's partitions are planned for responses this long; longer ones
  // get more partitions of its largest size. An image-source part to second or third
  // order in a room of a few metres ends within it.
  static constexpr double kPlannedEarlyResponseS = 0.1;

  // Throws InputError for a decoder that is not at 48 kHz or bad options.
  BinauralStream(BinauralDecoder decoder, const BinauralStreamOptions& options = {});
  ~BinauralStream();

  std::size_t blockSize() const { return options_.block_size; }
  int order() const { return decoder_.order; }
  bool hasRoom() const { return room_ != nullptr; }

  // An ambisonic (AmbiX, ACN/SN3D) room response at 48 kHz, order up to the decoder's.
  // Returns a warning ("" when none): truncation to max_response_s. Throws InputError for
  // a response of the wrong rate, a channel count that is not (n+1)^2 up to the decoder's
  // order, or non-finite samples (the stream keeps its previous room then).
  std::string setRoom(const AudioBuffer& ambix_response);
  // setRoom in two steps: prepareRoom does the checks and the transforms and may run on
  // any thread, beside process() (it reads only what the constructor set); setRoom of the
  // prepared response swaps it in (InputError for one prepared by another stream's
  // prepareEarlyResponse or a stream of other options).
  PreparedResponse prepareRoom(const AudioBuffer& ambix_response) const;
  std::string setRoom(const PreparedResponse& prepared);

  // Early reflections that move with the listener (reflection_tap_bank.h), of the stream's
  // order, added to the room's field before the head rotation; the response setRoom holds
  // is then what the taps leave out (an RSAO's late part). Null removes them. The previous
  // taps fade out over one block while the new ones fade in. Throws InputError for taps of
  // another order (the stream keeps its taps then).
  void setEarlyTaps(std::unique_ptr<ReflectionTapBank> taps);
  // The taps, to set their targets before a block; null when there are none.
  ReflectionTapBank* earlyTaps() { return taps_.get(); }

  // A second, short ambisonic response convolved beside the room's and added to its field:
  // the image-source part of a simulated room at the listener's position, changed as the
  // listener walks (simulated_walk.h); the room's response is then the late part. Each
  // change fades over early_crossfade_blocks on the same input history, so no reflection
  // is cut. The same checks and truncation as setRoom. An empty buffer removes it.
  std::string setEarlyResponse(const AudioBuffer& ambix_response);
  // The same in two steps, as prepareRoom and setRoom.
  PreparedResponse prepareEarlyResponse(const AudioBuffer& ambix_response) const;
  std::string setEarlyResponse(const PreparedResponse& prepared);

  // The listener's head orientation in the room frame (rotation.h). Throws InputError for a
  // malformed quaternion (the stream keeps the previous orientation then).
  void setHeadOrientation(const Eigen::Quaterniond& head_in_room);

  // One block: `source` holds blockSize() mono samples; writes blockSize() samples to each
  // ear. Non-finite source samples are played as zeros and counted. Silence until a room
  // is set.
  void process(const float* source, float* left, float* right);

  // Source samples replaced by zeros because they were NaN or infinite, since construction.
  std::size_t nonFiniteSamples() const { return non_finite_samples_; }

  const BinauralStreamOptions& options() const { return options_; }

 private:
  // The response as the convolver's 1 x channels_ matrix, padded and truncated (and, with
  // mixed_order, cut as options_.mixed_order_late says); its warning ("" when none).
  // InputError as setRoom says.
  FilterMatrix responseFilters(const AudioBuffer& response, const char* what, bool mixed_order,
                               std::string& warning) const;

  BinauralDecoder decoder_;
  BinauralStreamOptions options_;
  std::size_t channels_;
  // Fixed at construction, so that responses can be prepared before the first is set:
  // the room's for max_response_s (the longest the stream must keep up with), the early
  // part's for kPlannedEarlyResponseS. By partition_plan.h's cost model, under the plan
  // for the default 4 s a 2 s room costs 0.7 % more than under its own plan and a 0.5 s
  // room 26 % more (still less than the 2 s room).
  std::vector<PartitionLevel> room_plan_, early_plan_;
  std::unique_ptr<PartitionedConvolver> room_, early_;
  std::vector<std::vector<float>> early_field_;
  std::vector<float*> early_out_;
  std::unique_ptr<PartitionedConvolver> decoder_convolver_;
  std::unique_ptr<ReflectionTapBank> taps_, retiring_taps_;
  Eigen::MatrixXd rotation_from_, rotation_to_;
  std::vector<float> source_block_;
  // The field before and after the head rotation, channel c's block at c * block_size.
  std::vector<float> field_, rotated_;
  std::vector<float> rotation_from_gains_, rotation_change_;  // per order block, as encodeGliding takes them
  std::vector<float> ramp_;                                   // (n + 1) / block_size
  std::vector<float*> field_out_, rotated_out_;
  std::vector<const float*> rotated_in_;
  std::size_t non_finite_samples_ = 0;
};

}  // namespace room_reverb::core
