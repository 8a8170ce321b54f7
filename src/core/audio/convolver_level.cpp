#include "convolver_level.h"

#include <algorithm>
#include <limits>

#include "spectral_kernels.h"

namespace room_reverb::core {

ConvolverLevel::ConvolverLevel(const PartitionLevel& plan, bool open_ended, std::size_t block_size,
                               std::size_t inputs, std::size_t outputs)
    : plan_(plan),
      open_ended_(open_ended),
      block_size_(block_size),
      calls_per_block_(plan.partition_size / block_size),
      spread_(spreadCalls(plan, block_size)),
      inputs_(inputs),
      outputs_(outputs),
      bins_(plan.partition_size + 1),
      stride_(rowStride(bins_)),
      // Measured plans (fft.h says what they gain): a stream's transforms of 512 to 32 768
      // points cost about 1.5 s to measure at its first start on a machine, nothing after.
      fft_(2 * plan.partition_size, FftPlanning::kMeasured),
      groups_((outputs + kOutputGroup - 1) / kOutputGroup),
      units_(inputs + groups_ * (inputs + 1)),
      next_unit_(units_),
      fft_unit_cost_(fftCost(2 * plan.partition_size)) {
  reserve(plan.partitions);
}

LevelSpectra ConvolverLevel::transform(const PartitionLevel& plan, bool open_ended, std::size_t inputs,
                                       std::size_t outputs, const FilterMatrix& filters, std::size_t longest) {
  const std::size_t p = plan.partition_size;
  const std::size_t bins = p + 1, stride = rowStride(bins);
  RealFft fft(2 * p);
  std::vector<float> time(2 * p);
  std::vector<std::complex<float>> spectrum(bins);
  const float scale = 1.0f / static_cast<float>(2 * p);
  LevelSpectra spectra;
  spectra.partitions = longest > plan.first_tap ? (longest - plan.first_tap + p - 1) / p : 0;
  if (!open_ended) spectra.partitions = std::min(spectra.partitions, plan.partitions);
  spectra.rows.assign(outputs * inputs * spectra.partitions * 2 * stride, 0.0f);
  // Partition q holds taps [D + qP, D + (q+1)P), zero-padded to 2P: against the 2P input
  // window the last P samples of the circular convolution are then the linear convolution.
  spectra.used.assign(outputs * inputs, 0);
  spectra.output_used.assign(outputs, 0);
  spectra.leading.assign(outputs * inputs, 0);
  float* row = spectra.rows.data();
  for (std::size_t o = 0; o < outputs; ++o) {
    for (std::size_t i = 0; i < inputs; ++i) {
      const auto& taps = filters[i][o];
      std::size_t length = taps.size();
      while (length > 0 && taps[length - 1] == 0.0f) --length;
      const std::size_t used = length > plan.first_tap ? (length - plan.first_tap + p - 1) / p : 0;
      spectra.used[o * inputs + i] = std::min(used, spectra.partitions);
      std::size_t first_non_zero = 0;
      while (first_non_zero < length && taps[first_non_zero] == 0.0f) ++first_non_zero;
      const std::size_t leading = first_non_zero > plan.first_tap ? (first_non_zero - plan.first_tap) / p : 0;
      spectra.leading[o * inputs + i] = std::min(leading, spectra.used[o * inputs + i]);
      spectra.output_used[o] = std::max(spectra.output_used[o], spectra.used[o * inputs + i]);
      for (std::size_t q = 0; q < spectra.partitions; ++q, row += 2 * stride) {
        const std::size_t begin = std::min(taps.size(), plan.first_tap + q * p);
        const std::size_t end = std::min(taps.size(), begin + p);
        std::fill(time.begin(), time.end(), 0.0f);
        std::copy(taps.begin() + begin, taps.begin() + end, time.begin());
        fft.forward(time.data(), spectrum.data());
        splitSpectrum(spectrum.data(), bins, row, stride);
        // The inverse transform of the output is left unnormalised (finishOutputs): its
        // 1 / 2P is applied here once.
        for (std::size_t k = 0; k < 2 * stride; ++k) row[k] *= scale;
      }
    }
  }
  return spectra;
}

void ConvolverLevel::reserve(std::size_t partitions) {
  // Besides the n blocks one output needs, catchUp() reaches back to the oldest block
  // whose output is still ahead of the stream: floor(D / P) + 1 blocks more.
  const std::size_t capacity = partitions + plan_.first_tap / plan_.partition_size + 1;
  if (capacity <= capacity_) return;
  // Re-lay the kept blocks by their absolute index; the new slots hold blocks older than
  // were kept, i.e. silence.
  const std::size_t slot_floats = inputs_ * 2 * stride_;
  std::vector<float> grown(capacity * slot_floats, 0.0f);
  for (std::int64_t m = std::max<std::int64_t>(0, block_ - static_cast<std::int64_t>(capacity_) + 1); m <= block_; ++m) {
    std::copy_n(&delay_line_[slotOf(m) * slot_floats], slot_floats,
                &grown[static_cast<std::size_t>(m) % capacity * slot_floats]);
  }
  capacity_ = capacity;
  delay_line_ = std::move(grown);
  // The schedule's cost estimate follows the most partitions any set has here.
  mac_unit_cost_ = std::max(partitions, plan_.partitions) * multiplyAddCost(bins_);
  block_cost_ = (inputs_ + outputs_) * fft_unit_cost_ + inputs_ * outputs_ * mac_unit_cost_;
}

std::size_t ConvolverLevel::slotOf(std::int64_t block) const {
  const auto capacity = static_cast<std::int64_t>(capacity_);
  return static_cast<std::size_t>(((block % capacity) + capacity) % capacity);
}

const float* ConvolverLevel::slotRow(std::int64_t block, std::size_t input) const {
  return &delay_line_[(slotOf(block) * inputs_ + input) * 2 * stride_];
}

float* ConvolverLevel::slotRow(std::int64_t block, std::size_t input) {
  return &delay_line_[(slotOf(block) * inputs_ + input) * 2 * stride_];
}

std::size_t ConvolverLevel::groupSize(std::size_t group) const {
  return std::min(kOutputGroup, outputs_ - group * kOutputGroup);
}

double ConvolverLevel::unitCost(std::size_t unit) const {
  if (unit < inputs_) return fft_unit_cost_;
  const std::size_t outputs = groupSize((unit - inputs_) / (inputs_ + 1));
  return outputs * ((unit - inputs_) % (inputs_ + 1) == inputs_ ? fft_unit_cost_ : mac_unit_cost_);
}

void ConvolverLevel::run(std::int64_t call, const SampleRing& input, const LevelTarget* targets, std::size_t count) {
  const auto slice = static_cast<std::size_t>((call + 1) % static_cast<std::int64_t>(calls_per_block_));
  if (slice == 0) {
    block_ = blockOfCall(call);
    next_unit_ = 0;
    done_cost_ = 0.0;
  }
  // This call's share: the block's cost up to (slice + 1) / spread, the rest in its last
  // allowed call.
  const double budget = slice + 1 >= spread_ ? std::numeric_limits<double>::infinity()
                                             : block_cost_ * static_cast<double>(slice + 1) / spread_;
  while (next_unit_ < units_ && done_cost_ < budget) {
    runUnit(next_unit_, input, targets, count);
    done_cost_ += unitCost(next_unit_);
    ++next_unit_;
  }
}

void ConvolverLevel::runUnit(std::size_t unit, const SampleRing& input, const LevelTarget* targets,
                             std::size_t count) {
  if (unit < inputs_) {
    transformInput(block_, unit, input);
    return;
  }
  const std::size_t group = (unit - inputs_) / (inputs_ + 1);
  const std::size_t step = (unit - inputs_) % (inputs_ + 1);
  for (std::size_t t = 0; t < count; ++t) {
    if (targets[t].spectra->partitions == 0) continue;
    if (step < inputs_) {
      multiplyAdd(block_, group, step, targets[t]);
    } else {
      finishOutputs(block_, group, targets[t], std::numeric_limits<std::int64_t>::min());
    }
  }
}

void ConvolverLevel::finishInputTransforms(const SampleRing& input) {
  while (next_unit_ < inputs_) {
    transformInput(block_, next_unit_, input);
    done_cost_ += unitCost(next_unit_);
    ++next_unit_;
  }
}

void ConvolverLevel::catchUp(std::int64_t next_call, const SampleRing& input, const LevelTarget& target) {
  const std::int64_t newest = blockOfCall(next_call - 1);
  if (newest < 0 || target.spectra->partitions == 0) return;
  finishInputTransforms(input);
  const std::int64_t from = next_call * static_cast<std::int64_t>(block_size_);
  const auto p = static_cast<std::int64_t>(plan_.partition_size);
  // Older blocks' outputs end earlier; stop at the first one already played.
  for (std::int64_t m = newest; m >= 0 && outputBegin(m) + p > from; --m) {
    for (std::size_t g = 0; g < groups_; ++g) {
      for (std::size_t i = 0; i < inputs_; ++i) multiplyAdd(m, g, i, target);
      finishOutputs(m, g, target, from);
    }
  }
}

void ConvolverLevel::reset() {
  std::fill(delay_line_.begin(), delay_line_.end(), 0.0f);
  next_unit_ = units_;
}

void ConvolverLevel::transformInput(std::int64_t block, std::size_t input, const SampleRing& ring) {
  // The 2P-frame window ending with the block (overlap-save).
  const auto p = static_cast<std::int64_t>(plan_.partition_size);
  ring.read(input, (block - 1) * p, fft_.timeData(), fft_.size());
  fft_.forwardInPlace();
  splitSpectrum(fft_.spectrumData(), bins_, slotRow(block, input), stride_);
}

void ConvolverLevel::multiplyAdd(std::int64_t block, std::size_t group, std::size_t input,
                                 const LevelTarget& target) const {
  const std::size_t partitions = target.spectra->partitions;
  const std::size_t first = group * kOutputGroup, count = groupSize(group);
  float* y = target.accumulator;
  if (input == 0) std::fill_n(y, count * 2 * stride_, 0.0f);
  // Partition q of the filter meets the input block q blocks older. The group's outputs
  // run together over the partitions they all use, from the first that is not zero in
  // all of them (outputs whose filter from this input is zero here drop out); each then
  // finishes its own alone.
  const float* h[kOutputGroup];
  float* acc[kOutputGroup];
  std::size_t used[kOutputGroup];
  std::size_t active = 0, common = partitions, leading = partitions;
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t filter = (first + j) * inputs_ + input;
    const std::size_t u = target.spectra->used[filter];
    if (u == 0) continue;
    h[active] = &target.spectra->rows[filter * partitions * 2 * stride_];
    acc[active] = y + j * 2 * stride_;
    used[active] = u;
    common = std::min(common, u);
    leading = std::min(leading, target.spectra->leading[filter]);
    ++active;
  }
  if (active == 0) return;
  const std::size_t slot_step = inputs_ * 2 * stride_;
  const float* ring = delay_line_.data() + input * 2 * stride_;
  // Partitions [from, to) of the given outputs' filters.
  const auto accumulate = [&](std::size_t from, std::size_t to, const float* const* filters, std::size_t n,
                              float* const* sums) {
    if (to <= from) return;
    const float* starts[kOutputGroup];
    for (std::size_t j = 0; j < n; ++j) starts[j] = filters[j] + from * 2 * stride_;
    const DelayLineRows rows{ring, capacity_, slot_step, slotOf(block - static_cast<std::int64_t>(from))};
    multiplyAccumulateOutputs(rows, to - from, starts, 2 * stride_, n, sums, stride_);
  };
  accumulate(leading, common, h, active, acc);
  for (std::size_t j = 0; j < active; ++j) accumulate(std::max(common, leading), used[j], &h[j], 1, &acc[j]);
}

void ConvolverLevel::finishOutputs(std::int64_t block, std::size_t group, const LevelTarget& target,
                                   std::int64_t from_frame) {
  const std::size_t p = plan_.partition_size;
  const std::int64_t begin = outputBegin(block);
  const std::size_t skip = from_frame > begin ? std::min(static_cast<std::size_t>(from_frame - begin), p) : 0;
  for (std::size_t j = 0; j < groupSize(group); ++j) {
    const std::size_t output = group * kOutputGroup + j;
    if (target.spectra->output_used[output] == 0) continue;  // every filter of this output is zero here
    joinSpectrum(target.accumulator + j * 2 * stride_, stride_, bins_, fft_.spectrumData());
    fft_.inverseInPlace();  // normalised by the filter spectra's scale (transform)
    // The second half of the 2P-point result is the linear convolution (overlap-save).
    target.output->add(output, begin + static_cast<std::int64_t>(skip), fft_.timeData() + p + skip, p - skip);
  }
}

}  // namespace room_reverb::core
