#include "room_reverb/audio/fft.h"

#include <fftw3.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>

namespace room_reverb::core {

std::size_t nextFastFftSize(std::size_t n) {
  if (n <= 1) return 1;
  for (std::size_t candidate = n;; ++candidate) {
    std::size_t rest = candidate;
    for (std::size_t factor : {2u, 3u, 5u, 7u}) {
      while (rest % factor == 0) rest /= factor;
    }
    if (rest == 1) return candidate;
  }
}

struct RealFft::Plans {
  fftwf_plan forward = nullptr;
  fftwf_plan inverse = nullptr;
  ~Plans() {
    if (forward) fftwf_destroy_plan(forward);
    if (inverse) fftwf_destroy_plan(inverse);
  }
};

namespace {

std::mutex& plannerMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

RealFft::RealFft(std::size_t size) : size_(size) {
  if (size == 0) throw std::invalid_argument("RealFft size must be positive");
  time_buffer_ = fftwf_alloc_real(size_);
  spectrum_buffer_ = fftwf_alloc_complex(spectrumSize());
  if (!time_buffer_ || !spectrum_buffer_) throw std::bad_alloc();

  std::lock_guard<std::mutex> lock(plannerMutex());
  static std::map<std::size_t, std::shared_ptr<const Plans>> cache;
  auto found = cache.find(size_);
  if (found != cache.end()) {
    plans_ = found->second;
    return;
  }
  // FFTW_ESTIMATE: measuring would cost seconds for the long transforms of whole RIRs and
  // plans are executed on other buffers of the same (fftwf_malloc) alignment.
  auto plans = std::make_shared<Plans>();
  auto* spectrum = static_cast<fftwf_complex*>(spectrum_buffer_);
  const int n = static_cast<int>(size_);
  plans->forward = fftwf_plan_dft_r2c_1d(n, time_buffer_, spectrum, FFTW_ESTIMATE);
  plans->inverse = fftwf_plan_dft_c2r_1d(n, spectrum, time_buffer_, FFTW_ESTIMATE);
  if (!plans->forward || !plans->inverse) throw std::runtime_error("FFTW could not plan");
  cache.emplace(size_, plans);
  plans_ = plans;
}

RealFft::~RealFft() {
  fftwf_free(time_buffer_);
  fftwf_free(spectrum_buffer_);
}

void RealFft::forward(const float* time, std::complex<float>* spectrum) {
  std::memcpy(time_buffer_, time, size_ * sizeof(float));
  auto* buffer = static_cast<fftwf_complex*>(spectrum_buffer_);
  fftwf_execute_dft_r2c(plans_->forward, time_buffer_, buffer);
  std::memcpy(static_cast<void*>(spectrum), buffer, spectrumSize() * sizeof(fftwf_complex));
}

void RealFft::inverse(const std::complex<float>* spectrum, float* time) {
  auto* buffer = static_cast<fftwf_complex*>(spectrum_buffer_);
  std::memcpy(buffer, static_cast<const void*>(spectrum), spectrumSize() * sizeof(fftwf_complex));
  fftwf_execute_dft_c2r(plans_->inverse, buffer, time_buffer_);
  const float scale = 1.0f / static_cast<float>(size_);
  for (std::size_t n = 0; n < size_; ++n) time[n] = time_buffer_[n] * scale;
}

std::vector<std::complex<float>> RealFft::forward(const std::vector<float>& time) {
  if (time.size() != size_) throw std::invalid_argument("RealFft::forward: wrong input length");
  std::vector<std::complex<float>> spectrum(spectrumSize());
  forward(time.data(), spectrum.data());
  return spectrum;
}

std::vector<float> RealFft::inverse(const std::vector<std::complex<float>>& spectrum) {
  if (spectrum.size() != spectrumSize()) {
    throw std::invalid_argument("RealFft::inverse: wrong spectrum length");
  }
  std::vector<float> time(size_);
  inverse(spectrum.data(), time.data());
  return time;
}

}  // namespace room_reverb::core
