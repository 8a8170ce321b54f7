#include "room_reverb/audio/partitioned_convolver.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <utility>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

// One filter matrix in the frequency domain: for partition p, input i, output o (in that
// nesting, the order render() walks them, so the largest array streams through memory
// once per block) a split spectrum of stride_ real parts then stride_ imaginary parts.
struct PartitionedConvolver::FilterSpectra {
  std::size_t partitions = 0;
  std::vector<float> rows;
};

namespace {

// Spectra are kept as split real/imaginary rows padded to a multiple of this many floats
// (one 64-byte cache line), so the multiply-add loop runs over whole SIMD vectors.
constexpr std::size_t kRowAlignmentFloats = 16;

std::size_t ceilDiv(std::size_t a, std::size_t b) { return (a + b - 1) / b; }

// y += x * h over n bins of split complex rows. The hot loop of the convolver: restrict
// lets the compiler vectorise it.
void multiplyAccumulate(const float* __restrict x_re, const float* __restrict x_im,
                        const float* __restrict h_re, const float* __restrict h_im,
                        float* __restrict y_re, float* __restrict y_im, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) {
    y_re[k] += x_re[k] * h_re[k] - x_im[k] * h_im[k];
    y_im[k] += x_re[k] * h_im[k] + x_im[k] * h_re[k];
  }
}

void splitSpectrum(const std::complex<float>* spectrum, std::size_t bins, float* re, float* im) {
  for (std::size_t k = 0; k < bins; ++k) {
    re[k] = spectrum[k].real();
    im[k] = spectrum[k].imag();
  }
}

void joinSpectrum(const float* re, const float* im, std::size_t bins, std::complex<float>* spectrum) {
  for (std::size_t k = 0; k < bins; ++k) spectrum[k] = {re[k], im[k]};
}

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

}  // namespace

PartitionedConvolver::PartitionedConvolver(const FilterMatrix& filters, std::size_t block_size,
                                           std::size_t crossfade_blocks)
    : input_count_(filters.size()),
      output_count_(validateMatrix(filters)),
      block_size_(block_size),
      crossfade_blocks_(crossfade_blocks),
      bins_(block_size + 1),
      stride_(ceilDiv(block_size + 1, kRowAlignmentFloats) * kRowAlignmentFloats),
      fft_(block_size == 0 ? 1 : 2 * block_size),
      fade_block_(crossfade_blocks),
      capacity_(0),
      newest_slot_(0) {
  if (block_size == 0) throw InputError("convolver block size is 0; use a positive size such as 256 frames");
  if (crossfade_blocks == 0) throw InputError("convolver crossfade is 0 blocks; use at least 1 so a filter swap does not click");
  spectrum_.resize(bins_);
  time_.resize(2 * block_size_);
  input_windows_.assign(input_count_ * 2 * block_size_, 0.0f);
  accumulators_.assign(output_count_ * 2 * stride_, 0.0f);
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

  current_ = transform(filters);
  growDelayLine(current_->partitions);
}

PartitionedConvolver::~PartitionedConvolver() = default;

std::size_t PartitionedConvolver::partitionCount() const { return current_->partitions; }

std::unique_ptr<PartitionedConvolver::FilterSpectra> PartitionedConvolver::transform(
    const FilterMatrix& filters) {
  const std::size_t outputs = validateMatrix(filters);
  if (filters.size() != input_count_ || outputs != output_count_) {
    std::ostringstream os;
    os << "new filter matrix is " << filters.size() << " inputs x " << outputs << " outputs but the convolver runs "
       << input_count_ << " x " << output_count_ << "; make a new convolver to change the channel counts";
    throw InputError(os.str());
  }
  std::size_t longest = 0;
  for (const auto& row : filters) {
    for (const auto& taps : row) longest = std::max(longest, taps.size());
  }
  auto spectra = std::make_unique<FilterSpectra>();
  spectra->partitions = ceilDiv(longest, block_size_);
  spectra->rows.assign(spectra->partitions * input_count_ * output_count_ * 2 * stride_, 0.0f);

  // Partition p holds taps [pB, (p+1)B), zero-padded to 2B: against the 2B input window
  // the last B samples of the circular convolution are then the linear convolution.
  for (std::size_t p = 0; p < spectra->partitions; ++p) {
    for (std::size_t i = 0; i < input_count_; ++i) {
      for (std::size_t o = 0; o < output_count_; ++o) {
        const auto& taps = filters[i][o];
        const std::size_t begin = std::min(taps.size(), p * block_size_);
        const std::size_t end = std::min(taps.size(), begin + block_size_);
        std::fill(time_.begin(), time_.end(), 0.0f);
        std::copy(taps.begin() + begin, taps.begin() + end, time_.begin());
        fft_.forward(time_.data(), spectrum_.data());
        float* row = &spectra->rows[((p * input_count_ + i) * output_count_ + o) * 2 * stride_];
        splitSpectrum(spectrum_.data(), bins_, row, row + stride_);
      }
    }
  }
  return spectra;
}

void PartitionedConvolver::growDelayLine(std::size_t partitions) {
  if (partitions <= capacity_) return;
  // Re-lay the ring with the newest block in slot capacity_-1 and older blocks below it;
  // the new slots hold blocks older than were kept, i.e. silence.
  const std::size_t slot_floats = input_count_ * 2 * stride_;
  std::vector<float> grown(partitions * slot_floats, 0.0f);
  for (std::size_t age = 0; age < capacity_; ++age) {
    const std::size_t from = (newest_slot_ + capacity_ - age) % capacity_;
    const std::size_t to = capacity_ - 1 - age;
    std::copy_n(&delay_line_[from * slot_floats], slot_floats, &grown[to * slot_floats]);
  }
  newest_slot_ = capacity_ == 0 ? 0 : capacity_ - 1;
  capacity_ = partitions;
  delay_line_ = std::move(grown);
}

void PartitionedConvolver::setFilters(const FilterMatrix& filters) {
  auto spectra = transform(filters);
  growDelayLine(spectra->partitions);
  pending_ = std::move(spectra);  // frees a stale set here, never in process()
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
}

void PartitionedConvolver::reset() {
  std::fill(delay_line_.begin(), delay_line_.end(), 0.0f);
  std::fill(input_windows_.begin(), input_windows_.end(), 0.0f);
  if (swap_waiting_) startPendingFade();
  fade_block_ = crossfade_blocks_;
}

void PartitionedConvolver::pushInputs(const float* const* inputs) {
  newest_slot_ = (newest_slot_ + 1) % capacity_;
  const std::size_t b = block_size_;
  for (std::size_t i = 0; i < input_count_; ++i) {
    float* window = &input_windows_[i * 2 * b];
    std::memmove(window, window + b, b * sizeof(float));
    std::memcpy(window + b, inputs[i], b * sizeof(float));
    fft_.forward(window, spectrum_.data());
    float* row = &delay_line_[(newest_slot_ * input_count_ + i) * 2 * stride_];
    splitSpectrum(spectrum_.data(), bins_, row, row + stride_);
  }
}

void PartitionedConvolver::render(const FilterSpectra& spectra, float* const* outputs) {
  std::fill(accumulators_.begin(), accumulators_.end(), 0.0f);
  const std::size_t row_pair = 2 * stride_;
  for (std::size_t p = 0; p < spectra.partitions; ++p) {
    const std::size_t slot = (newest_slot_ + capacity_ - p) % capacity_;
    const float* x = &delay_line_[slot * input_count_ * row_pair];
    const float* h = &spectra.rows[p * input_count_ * output_count_ * row_pair];
    for (std::size_t i = 0; i < input_count_; ++i, x += row_pair) {
      float* y = accumulators_.data();
      for (std::size_t o = 0; o < output_count_; ++o, h += row_pair, y += row_pair) {
        multiplyAccumulate(x, x + stride_, h, h + stride_, y, y + stride_, stride_);
      }
    }
  }
  for (std::size_t o = 0; o < output_count_; ++o) {
    const float* y = &accumulators_[o * row_pair];
    joinSpectrum(y, y + stride_, bins_, spectrum_.data());
    fft_.inverse(spectrum_.data(), time_.data());
    std::copy_n(time_.data() + block_size_, block_size_, outputs[o]);
  }
}

void PartitionedConvolver::process(const float* const* inputs, float* const* outputs) {
  if (!crossfading() && swap_waiting_) startPendingFade();
  pushInputs(inputs);
  render(*current_, outputs);
  if (!crossfading()) return;
  render(*previous_, fade_out_pointers_.data());
  const float* gain = &fade_in_gain_[fade_block_ * block_size_];
  for (std::size_t o = 0; o < output_count_; ++o) {
    const float* old_out = fade_out_pointers_[o];
    float* out = outputs[o];
    for (std::size_t n = 0; n < block_size_; ++n) out[n] = old_out[n] + gain[n] * (out[n] - old_out[n]);
  }
  ++fade_block_;
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
