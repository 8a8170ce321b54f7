#include "room_reverb/binaural/binaural_stream.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/ambisonics/rotation.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/binaural/late_order.h"
#include "room_reverb/common/error.h"
#include "tap_kernels.h"

namespace room_reverb::core {
namespace {

FilterMatrix decoderMatrix(const BinauralDecoder& decoder) {
  FilterMatrix m(decoder.filters.size());
  for (std::size_t c = 0; c < m.size(); ++c) m[c] = {decoder.filters[c].left, decoder.filters[c].right};
  return m;
}

}  // namespace

BinauralStream::BinauralStream(BinauralDecoder decoder, const BinauralStreamOptions& options)
    : decoder_(std::move(decoder)), options_(options) {
  if (decoder_.sample_rate_hz != kInternalSampleRateHz) {
    throw InputError("binaural stream: the decoder is at " + std::to_string(decoder_.sample_rate_hz) +
                     " Hz; make it from an HRTF set resampled to 48000 Hz");
  }
  if (options_.block_size == 0 || options_.crossfade_blocks == 0 || options_.early_crossfade_blocks == 0 ||
      !(options_.max_response_s > 0.0)) {
    throw InputError("binaural stream: block_size and the crossfades' blocks must be positive, max_response_s too");
  }
  if (!std::isfinite(options_.full_order_s) || options_.full_order_s < 0.0) {
    throw InputError("binaural stream: full_order_s must be a finite time >= 0 s");
  }
  channels_ = static_cast<std::size_t>(ambisonicChannelCount(decoder_.order));
  if (decoder_.filters.size() != channels_) throw InputError("binaural stream: the decoder's filter count does not match its order");
  decoder_convolver_ = std::make_unique<PartitionedConvolver>(decoderMatrix(decoder_), options_.block_size, 1);
  const auto planned = [&](double seconds, std::size_t max_partition) {
    const auto frames = static_cast<std::size_t>(std::ceil(seconds * kInternalSampleRateHz));
    return planPartitions(std::max<std::size_t>(frames, 1), options_.block_size, max_partition, 1, channels_);
  };
  room_plan_ = planned(options_.max_response_s, PartitionedConvolver::kDefaultMaxPartitionSize);
  // The early part is uniformly partitioned: it changes every chunk or two while the
  // listener walks, and a new response under a uniform plan starts from the delay line
  // alone, where larger partitions would first have to compute their outputs in flight
  // (bench_binaural_renderer, BM_SimulatedWalkChunk: a change every chunk costs 15 % less
  // of the whole stream, one every two chunks 6 % less).
  early_plan_ = planned(std::min(kPlannedEarlyResponseS, options_.max_response_s), options_.block_size);
  rotation_from_ = rotation_to_ = Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(channels_), static_cast<Eigen::Index>(channels_));
  source_block_.assign(options_.block_size, 0.0f);
  field_.assign(channels_ * options_.block_size, 0.0f);
  rotated_ = field_;
  rotation_from_gains_.assign(channels_ * channels_, 0.0f);
  rotation_change_ = rotation_from_gains_;
  ramp_.resize(options_.block_size);
  for (std::size_t n = 0; n < ramp_.size(); ++n) {
    ramp_[n] = static_cast<float>(static_cast<double>(n + 1) / static_cast<double>(options_.block_size));
  }
  for (std::size_t c = 0; c < channels_; ++c) {
    field_out_.push_back(field_.data() + c * options_.block_size);
    rotated_out_.push_back(rotated_.data() + c * options_.block_size);
    rotated_in_.push_back(rotated_out_.back());
  }
}

BinauralStream::~BinauralStream() = default;

AudioBuffer roomResponseAsStreamed(const AudioBuffer& ambix, const BinauralDecoder& decoder,
                                   const BinauralStreamOptions& options) {
  if (!options.mixed_order_late || ambixOrder(ambix) < 2) return ambix;
  return reduceLateOrder(ambix, decoder, options.full_order_s);
}

FilterMatrix BinauralStream::responseFilters(const AudioBuffer& checked, const char* what, bool mixed_order,
                                             std::string& warning) const {
  validateAudioBuffer(checked, std::string("binaural stream: the ") + what);
  if (checked.sample_rate_hz != kInternalSampleRateHz) {
    throw InputError(std::string("binaural stream: the ") + what + " is at " + std::to_string(checked.sample_rate_hz) +
                     " Hz; resample it to 48000 Hz");
  }
  const int order = ambixOrder(checked, std::string("the ") + what);
  if (order > decoder_.order) {
    throw InputError("binaural stream: an order-" + std::to_string(order) + " " + what +
                     " cannot go through the order-" + std::to_string(decoder_.order) + " decoder");
  }
  // A mixed-order room is cut once the response has passed the checks (late_order.h), as
  // roomResponseAsStreamed cuts it.
  const AudioBuffer cut = mixed_order && order >= 2 ? reduceLateOrder(checked, decoder_, options_.full_order_s) : AudioBuffer{};
  const AudioBuffer& response = cut.channelCount() > 0 ? cut : checked;
  const std::size_t count = response.channelCount();
  const auto limit = static_cast<std::size_t>(options_.max_response_s * kInternalSampleRateHz);
  FilterMatrix filters(1, std::vector<std::vector<float>>(channels_, std::vector<float>{0.0f}));
  for (std::size_t c = 0; c < count; ++c) filters[0][c] = response.channels[c];
  if (response.frameCount() > limit) {
    for (std::size_t c = 0; c < count; ++c) filters[0][c].resize(limit);
    std::ostringstream os;
    os << "the " << what << " (" << response.durationS() << " s) was truncated to max_response_s = "
       << options_.max_response_s << " s";
    warning = os.str();
  }
  return filters;
}

PreparedResponse BinauralStream::prepareRoom(const AudioBuffer& response) const {
  PreparedResponse prepared;
  // Cut only a response the checks will accept (responseFilters says why not otherwise).
  prepared.filters = PartitionedConvolver::prepare(
      responseFilters(response, "room response", options_.mixed_order_late, prepared.warning), room_plan_,
      options_.block_size);
  return prepared;
}

PreparedResponse BinauralStream::prepareEarlyResponse(const AudioBuffer& response) const {
  PreparedResponse prepared;
  prepared.empty = response.frameCount() == 0;
  // None: faded out like any change, then left silent (a single zero tap costs nothing).
  const FilterMatrix filters = response.frameCount() == 0
                                   ? FilterMatrix(1, std::vector<std::vector<float>>(channels_, std::vector<float>{0.0f}))
                                   : responseFilters(response, "early response", false, prepared.warning);
  prepared.filters = PartitionedConvolver::prepare(filters, early_plan_, options_.block_size);
  return prepared;
}

std::string BinauralStream::setRoom(const AudioBuffer& response) { return setRoom(prepareRoom(response)); }

std::string BinauralStream::setRoom(const PreparedResponse& prepared) {
  if (room_) {
    room_->setFilters(prepared.filters);
  } else {
    room_ = std::make_unique<PartitionedConvolver>(prepared.filters, options_.crossfade_blocks);
  }
  return prepared.warning;
}

std::string BinauralStream::setEarlyResponse(const AudioBuffer& response) {
  return setEarlyResponse(prepareEarlyResponse(response));
}

std::string BinauralStream::setEarlyResponse(const PreparedResponse& prepared) {
  if (!early_ && prepared.empty) return prepared.warning;
  if (early_) {
    early_->setFilters(prepared.filters);
  } else {
    early_ = std::make_unique<PartitionedConvolver>(prepared.filters, options_.early_crossfade_blocks);
    early_field_.assign(channels_, std::vector<float>(options_.block_size, 0.0f));
    early_out_.clear();
    for (auto& channel : early_field_) early_out_.push_back(channel.data());
  }
  return prepared.warning;
}

void BinauralStream::setHeadOrientation(const Eigen::Quaterniond& head_in_room) {
  rotation_to_ = headTrackingRotation(head_in_room, decoder_.order);
}

void BinauralStream::setEarlyTaps(std::unique_ptr<ReflectionTapBank> taps) {
  if (taps && taps->channels() != channels_) {
    throw InputError("binaural stream: early taps of " + std::to_string(taps->channels()) + " channels for a stream of " +
                     std::to_string(channels_));
  }
  if (taps_) {
    taps_->fadeOut();
    retiring_taps_ = std::move(taps_);
  }
  taps_ = std::move(taps);
}

void BinauralStream::process(const float* source, float* left, float* right) {
  const std::size_t frames = options_.block_size;
  for (std::size_t n = 0; n < frames; ++n) {
    const bool finite = std::isfinite(source[n]);
    non_finite_samples_ += finite ? 0 : 1;
    source_block_[n] = finite ? source[n] : 0.0f;
  }
  float* ears[2] = {left, right};
  if (!room_) {
    for (float* ear : ears) std::fill(ear, ear + frames, 0.0f);
    return;
  }
  const float* input = source_block_.data();
  room_->process(&input, field_out_.data());
  if (early_) {
    early_->process(&input, early_out_.data());
    for (std::size_t c = 0; c < channels_; ++c) {
      float* __restrict out = field_out_[c];
      const float* __restrict early = early_field_[c].data();
      for (std::size_t n = 0; n < frames; ++n) out[n] += early[n];
    }
  }
  if (retiring_taps_) {
    retiring_taps_->process(input, field_out_.data());
    retiring_taps_.reset();
  }
  if (taps_) taps_->process(input, field_out_.data());
  // Rotation, moving linearly from last block's matrix to this one's across the block:
  // ((1 - u) R_from + u R_to) x. A rotation of spherical harmonics mixes only channels of
  // one order (ACN blocks of 1, 3, 5, 7), so each block is encoded on its own, as the
  // taps are (tap_kernels.h: the channels' sum held in registers over a tile of samples;
  // a per-sample 16 x 16 product in double takes a fifth of a walking stream's time).
  std::fill(rotated_.begin(), rotated_.end(), 0.0f);
  for (int l = 0; l <= decoder_.order; ++l) {
    const auto first = static_cast<std::size_t>(l * l), size = static_cast<std::size_t>(2 * l + 1);
    // Gains of input k (a channel of the order) into output c, at k * size + c.
    for (std::size_t k = 0; k < size; ++k) {
      for (std::size_t c = 0; c < size; ++c) {
        const auto row = static_cast<Eigen::Index>(first + c), column = static_cast<Eigen::Index>(first + k);
        rotation_from_gains_[k * size + c] = static_cast<float>(rotation_from_(row, column));
        rotation_change_[k * size + c] = static_cast<float>(rotation_to_(row, column) - rotation_from_(row, column));
      }
    }
    encodeGliding(field_.data() + first * frames, size, rotation_from_gains_.data(), rotation_change_.data(), size,
                  ramp_.data(), rotated_out_.data() + first, frames);
  }
  rotation_from_ = rotation_to_;
  decoder_convolver_->process(rotated_in_.data(), ears);
}

}  // namespace room_reverb::core
