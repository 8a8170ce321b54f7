#include "room_reverb/binaural/binaural_stream.h"

#include <cmath>
#include <sstream>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/ambisonics/rotation.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/common/error.h"

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
  if (options_.block_size == 0 || options_.crossfade_blocks == 0 || !(options_.max_response_s > 0.0)) {
    throw InputError("binaural stream: block_size and crossfade_blocks must be positive, max_response_s too");
  }
  channels_ = static_cast<std::size_t>(ambisonicChannelCount(decoder_.order));
  if (decoder_.filters.size() != channels_) throw InputError("binaural stream: the decoder's filter count does not match its order");
  decoder_convolver_ = std::make_unique<PartitionedConvolver>(decoderMatrix(decoder_), options_.block_size, 1);
  rotation_from_ = rotation_to_ = Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(channels_), static_cast<Eigen::Index>(channels_));
  source_block_.assign(options_.block_size, 0.0f);
  field_.assign(channels_, std::vector<float>(options_.block_size, 0.0f));
  rotated_ = field_;
  for (std::size_t c = 0; c < channels_; ++c) {
    field_out_.push_back(field_[c].data());
    rotated_out_.push_back(rotated_[c].data());
    rotated_in_.push_back(rotated_[c].data());
  }
}

BinauralStream::~BinauralStream() = default;

std::string BinauralStream::setRoom(const AudioBuffer& response) {
  validateAudioBuffer(response, "binaural stream: the room response");
  if (response.sample_rate_hz != kInternalSampleRateHz) {
    throw InputError("binaural stream: the room response is at " + std::to_string(response.sample_rate_hz) +
                     " Hz; resample it to 48000 Hz");
  }
  const int order = ambixOrder(response);
  if (order > decoder_.order) {
    throw InputError("binaural stream: an order-" + std::to_string(order) + " room response cannot go through the order-" +
                     std::to_string(decoder_.order) + " decoder");
  }
  const std::size_t count = response.channelCount();
  std::string warning;
  const auto limit = static_cast<std::size_t>(options_.max_response_s * kInternalSampleRateHz);
  FilterMatrix filters(1, std::vector<std::vector<float>>(channels_, std::vector<float>{0.0f}));
  for (std::size_t c = 0; c < count; ++c) filters[0][c] = response.channels[c];
  if (response.frameCount() > limit) {
    for (std::size_t c = 0; c < count; ++c) filters[0][c].resize(limit);
    std::ostringstream os;
    os << "the room response (" << response.durationS() << " s) was truncated to max_response_s = "
       << options_.max_response_s << " s";
    warning = os.str();
  }
  if (room_) {
    room_->setFilters(filters);
  } else {
    room_ = std::make_unique<PartitionedConvolver>(filters, options_.block_size, options_.crossfade_blocks);
  }
  return warning;
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
  if (retiring_taps_) {
    retiring_taps_->process(input, field_out_.data());
    retiring_taps_.reset();
  }
  if (taps_) taps_->process(input, field_out_.data());
  // Rotation, moving linearly from last block's matrix to this one's across the block.
  const bool turning = rotation_from_ != rotation_to_;
  const auto k = static_cast<Eigen::Index>(channels_);
  for (std::size_t n = 0; n < frames; ++n) {
    const double u = turning ? static_cast<double>(n + 1) / static_cast<double>(frames) : 1.0;
    for (Eigen::Index o = 0; o < k; ++o) {
      double sum = 0.0;
      for (Eigen::Index i = 0; i < k; ++i) {
        const double m = turning ? (1.0 - u) * rotation_from_(o, i) + u * rotation_to_(o, i) : rotation_to_(o, i);
        sum += m * field_[static_cast<std::size_t>(i)][n];
      }
      rotated_[static_cast<std::size_t>(o)][n] = static_cast<float>(sum);
    }
  }
  rotation_from_ = rotation_to_;
  decoder_convolver_->process(rotated_in_.data(), ears);
}

}  // namespace room_reverb::core
