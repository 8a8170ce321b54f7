#include "room_reverb/audio/partitioned_convolver.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "convolver_level.h"
#include "room_reverb/common/error.h"
#include "sample_ring.h"

namespace room_reverb::core {

struct PreparedFilters {
  std::vector<PartitionLevel> plan;
  std::size_t block_size = 0;
  std::size_t inputs = 0;
  std::size_t outputs = 0;
  std::vector<LevelSpectra> levels;  // per level of the plan
  std::size_t partitions = 0;        // over all levels
};

// One filter matrix in the frequency domain, per level, and where its output goes.
struct PartitionedConvolver::FilterSet {
  std::shared_ptr<const PreparedFilters> prepared;
  std::vector<std::int64_t> first_block;            // per level: the first block process() runs for it
  std::vector<std::vector<float>> accumulators;     // per level: the output spectrum being summed
  std::unique_ptr<SampleRing> output;               // per output: the levels' sum, by stream frame

  LevelTarget target(std::size_t level) {
    return {&prepared->levels[level], accumulators[level].data(), output.get()};
  }
};

namespace {

std::size_t validateMatrix(const FilterMatrix& filters) {
  if (filters.empty()) throw InputError("filter matrix has no input channels; give one row of filters per input");
  const std::size_t outputs = filters.front().size();
  if (outputs == 0) throw InputError("filter matrix has no output channels; give one filter per output in each row");
  for (std::size_t i = 0; i < filters.size(); ++i) {
    if (filters[i].size() != outputs) {
      std::ostringstream os;
      os << "filter matrix row " << i << " has " << filters[i].size() << " filters but row 0 has " << outputs
         << "; every input needs one filter per output";
      throw InputError(os.str());
    }
    for (std::size_t o = 0; o < outputs; ++o) {
      const auto& taps = filters[i][o];
      if (taps.empty()) {
        std::ostringstream os;
        os << "filter " << i << "->" << o << " is empty; give at least one tap (a single 0 for no path)";
        throw InputError(os.str());
      }
      if (!std::all_of(taps.begin(), taps.end(), [](float t) { return std::isfinite(t); })) {
        std::ostringstream os;
        os << "filter " << i << "->" << o << " has non-finite taps; the filter data is corrupt";
        throw InputError(os.str());
      }
    }
  }
  return outputs;
}

std::size_t longestFilter(const FilterMatrix& filters) {
  std::size_t longest = 0;
  for (const auto& row : filters) {
    for (const auto& taps : row) longest = std::max(longest, taps.size());
  }
  return longest;
}

}  // namespace

PartitionedConvolver::PartitionedConvolver(const FilterMatrix& filters, std::size_t block_size,
                                           std::size_t crossfade_blocks, std::size_t max_partition_size)
    : input_count_(filters.size()),
      output_count_(validateMatrix(filters)),
      block_size_(block_size),
      crossfade_blocks_(crossfade_blocks),
      fade_block_(crossfade_blocks) {
  if (block_size == 0) throw InputError("convolver block size is 0; use a positive size such as 256 frames");
  setUp(planPartitions(longestFilter(filters), block_size, max_partition_size, input_count_, output_count_));
  current_ = makeSet(prepare(filters, plan_, block_size_));
}

PartitionedConvolver::PartitionedConvolver(std::shared_ptr<const PreparedFilters> first, std::size_t crossfade_blocks)
    : input_count_(first ? first->inputs : 0),
      output_count_(first ? first->outputs : 0),
      block_size_(first ? first->block_size : 0),
      crossfade_blocks_(crossfade_blocks),
      fade_block_(crossfade_blocks) {
  if (!first) throw InputError("convolver: no prepared filters");
  setUp(first->plan);
  current_ = makeSet(std::move(first));
}

void PartitionedConvolver::setUp(const std::vector<PartitionLevel>& plan) {
  if (crossfade_blocks_ == 0) throw InputError("convolver crossfade is 0 blocks; use at least 1 so a filter swap does not click");
  plan_ = plan;
  std::size_t largest = 0;
  for (std::size_t l = 0; l < plan_.size(); ++l) {
    levels_.push_back(std::make_unique<ConvolverLevel>(plan_[l], l + 1 == plan_.size(), block_size_, input_count_,
                                                       output_count_));
    largest = std::max(largest, plan_[l].partition_size);
  }
  // A level reads its 2P-frame window up to P - B frames after the window ends.
  input_ = std::make_unique<SampleRing>(input_count_, 3 * largest);
  targets_.resize(3);
  fade_out_samples_.assign(output_count_ * block_size_, 0.0f);
  for (std::size_t o = 0; o < output_count_; ++o) fade_out_pointers_.push_back(&fade_out_samples_[o * block_size_]);
  input_pointers_.resize(input_count_);
  output_pointers_.resize(output_count_);

  // Raised cosine, sampled at sample centres so the fade is symmetric: old + new gains
  // are exactly one at every sample.
  const std::size_t fade_length = crossfade_blocks_ * block_size_;
  fade_in_gain_.resize(fade_length);
  for (std::size_t n = 0; n < fade_length; ++n) {
    fade_in_gain_[n] = static_cast<float>(0.5 - 0.5 * std::cos(M_PI * (n + 0.5) / fade_length));
  }
}

PartitionedConvolver::~PartitionedConvolver() = default;

std::size_t PartitionedConvolver::partitionCount() const { return current_->prepared->partitions; }

std::shared_ptr<const PreparedFilters> PartitionedConvolver::prepare(const FilterMatrix& filters,
                                                                     const std::vector<PartitionLevel>& plan,
                                                                     std::size_t block_size) {
  const std::size_t outputs = validateMatrix(filters);
  if (plan.empty() || block_size == 0) throw InputError("convolver: prepared filters need a partition plan and a block size");
  auto prepared = std::make_shared<PreparedFilters>();
  prepared->plan = plan;
  prepared->block_size = block_size;
  prepared->inputs = filters.size();
  prepared->outputs = outputs;
  const std::size_t longest = longestFilter(filters);
  for (std::size_t l = 0; l < plan.size(); ++l) {
    prepared->levels.push_back(
        ConvolverLevel::transform(plan[l], l + 1 == plan.size(), filters.size(), outputs, filters, longest));
    prepared->partitions += prepared->levels.back().partitions;
  }
  return prepared;
}

std::unique_ptr<PartitionedConvolver::FilterSet> PartitionedConvolver::makeSet(
    std::shared_ptr<const PreparedFilters> prepared) {
  if (!prepared) throw InputError("convolver: no prepared filters");
  if (prepared->inputs != input_count_ || prepared->outputs != output_count_) {
    std::ostringstream os;
    os << "new filter matrix is " << prepared->inputs << " inputs x " << prepared->outputs
       << " outputs but the convolver runs " << input_count_ << " x " << output_count_
       << "; make a new convolver to change the channel counts";
    throw InputError(os.str());
  }
  const auto same_level = [](const PartitionLevel& a, const PartitionLevel& b) {
    return a.partition_size == b.partition_size && a.first_tap == b.first_tap && a.partitions == b.partitions;
  };
  if (prepared->block_size != block_size_ ||
      !std::equal(prepared->plan.begin(), prepared->plan.end(), plan_.begin(), plan_.end(), same_level)) {
    throw InputError("convolver: the filters were prepared for another partition plan or block size");
  }
  auto set = std::make_unique<FilterSet>();
  // A level writes up to D + B frames ahead of the frame being played (catchUp() up to D).
  std::size_t ahead = 0;
  for (const auto& level : plan_) ahead = std::max(ahead, level.first_tap + level.partition_size);
  set->output = std::make_unique<SampleRing>(output_count_, ahead + 2 * block_size_);
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    levels_[l]->reserve(prepared->levels[l].partitions);
    set->accumulators.emplace_back(levels_[l]->accumulatorFloats(), 0.0f);
  }
  set->prepared = std::move(prepared);
  // The new set joins the stream now: it gets the outputs of every block already under
  // way, and process() runs the later blocks for it.
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    levels_[l]->catchUp(calls_, *input_, set->target(l));
    set->first_block.push_back(levels_[l]->blockOfCall(calls_ - 1) + 1);
  }
  return set;
}

void PartitionedConvolver::setFilters(const FilterMatrix& filters) {
  setFilters(prepare(filters, plan_, block_size_));
}

void PartitionedConvolver::setFilters(std::shared_ptr<const PreparedFilters> prepared) {
  pending_ = makeSet(std::move(prepared));  // frees a stale set here, never in process()
  swap_waiting_ = true;
  if (!crossfading()) startPendingFade();
}

void PartitionedConvolver::startPendingFade() {
  // Swaps only: the set retired long ago lands in pending_ and stays allocated until the
  // next setFilters() replaces it.
  std::swap(previous_, current_);
  std::swap(current_, pending_);
  swap_waiting_ = false;
  fade_block_ = 0;
  fade_end_frame_ = (calls_ + static_cast<std::int64_t>(crossfade_blocks_)) * static_cast<std::int64_t>(block_size_);
}

void PartitionedConvolver::reset() {
  input_->clearAll();
  for (auto& level : levels_) level->reset();
  for (auto* set : {current_.get(), previous_.get(), pending_.get()}) {
    if (set) set->output->clearAll();
  }
  if (swap_waiting_) startPendingFade();
  fade_block_ = crossfade_blocks_;
}

std::size_t PartitionedConvolver::levelTargets(std::size_t level) {
  // The sets whose output needs this level's current block: the one playing, the one
  // fading out while the block's output overlaps the fade, and one waiting to fade in.
  // A set added after the block started got its share from catchUp().
  const std::int64_t block = levels_[level]->blockOfCall(calls_);
  std::size_t count = 0;
  if (current_->first_block[level] <= block) targets_[count++] = current_->target(level);
  if (crossfading() && levels_[level]->outputBegin(block) < fade_end_frame_) {
    targets_[count++] = previous_->target(level);
  }
  if (swap_waiting_ && pending_->first_block[level] <= block) targets_[count++] = pending_->target(level);
  return count;
}

void PartitionedConvolver::process(const float* const* inputs, float* const* outputs) {
  if (!crossfading() && swap_waiting_) startPendingFade();
  const std::int64_t frame = calls_ * static_cast<std::int64_t>(block_size_);
  for (std::size_t i = 0; i < input_count_; ++i) input_->write(i, frame, inputs[i], block_size_);
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    const std::size_t count = levelTargets(l);
    levels_[l]->run(calls_, *input_, targets_.data(), count);
  }
  for (std::size_t o = 0; o < output_count_; ++o) current_->output->read(o, frame, outputs[o], block_size_);
  if (crossfading()) {
    const float* gain = &fade_in_gain_[fade_block_ * block_size_];
    for (std::size_t o = 0; o < output_count_; ++o) {
      float* old_out = fade_out_pointers_[o];
      previous_->output->read(o, frame, old_out, block_size_);
      float* out = outputs[o];
      for (std::size_t n = 0; n < block_size_; ++n) out[n] = old_out[n] + gain[n] * (out[n] - old_out[n]);
    }
    ++fade_block_;
  }
  // Played frames are zeroed so the rings can wrap onto them.
  current_->output->clear(frame, block_size_);
  if (previous_) previous_->output->clear(frame, block_size_);
  if (swap_waiting_) pending_->output->clear(frame, block_size_);
  ++calls_;
}

void PartitionedConvolver::process(const AudioBuffer& input, AudioBuffer& output) {
  if (input.channelCount() != input_count_) {
    std::ostringstream os;
    os << "convolver input has " << input.channelCount() << " channels but the filters expect " << input_count_;
    throw InputError(os.str());
  }
  for (std::size_t i = 0; i < input_count_; ++i) {
    if (input.channels[i].size() != block_size_) {
      std::ostringstream os;
      os << "convolver input channel " << i << " has " << input.channels[i].size() << " frames; process() takes blocks of exactly "
         << block_size_;
      throw InputError(os.str());
    }
    input_pointers_[i] = input.channels[i].data();
  }
  output.sample_rate_hz = input.sample_rate_hz;
  output.channels.resize(output_count_);
  for (std::size_t o = 0; o < output_count_; ++o) {
    output.channels[o].resize(block_size_);
    output_pointers_[o] = output.channels[o].data();
  }
  process(input_pointers_.data(), output_pointers_.data());
}

}  // namespace room_reverb::core
