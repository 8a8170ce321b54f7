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

// The plans of one kind for `size`, made by `make` (under the planner's lock) the first
// time and shared after. FFTW_ESTIMATE throughout: measuring would cost seconds for the
// long transforms of whole RIRs, and plans are executed on other buffers of the same
// (fftwf_malloc) alignment.
template <typename PlanSet, typename Make>
std::shared_ptr<const PlanSet> sharedPlans(std::size_t size, Make make) {
  std::lock_guard<std::mutex> lock(plannerMutex());
  static std::map<std::size_t, std::shared_ptr<const PlanSet>> cache;
  auto found = cache.find(size);
  if (found != cache.end()) return found->second;
  std::shared_ptr<const PlanSet> plans = make();
  cache.emplace(size, plans);
  return plans;
}

}  // namespace

RealFft::RealFft(std::size_t size) : size_(size) {
  if (size == 0) throw std::invalid_argument("RealFft size must be positive");
  time_buffer_ = fftwf_alloc_real(size_);
  spectrum_buffer_ = fftwf_alloc_complex(spectrumSize());
  if (!time_buffer_ || !spectrum_buffer_) throw std::bad_alloc();
  plans_ = sharedPlans<Plans>(size_, [&] {
    auto plans = std::make_shared<Plans>();
    auto* spectrum = static_cast<fftwf_complex*>(spectrum_buffer_);
    const int n = static_cast<int>(size_);
    plans->forward = fftwf_plan_dft_r2c_1d(n, time_buffer_, spectrum, FFTW_ESTIMATE);
    plans->inverse = fftwf_plan_dft_c2r_1d(n, spectrum, time_buffer_, FFTW_ESTIMATE);
    if (!plans->forward || !plans->inverse) throw std::runtime_error("FFTW could not plan");
    return plans;
  });
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

void RealFft::forwardInPlace() {
  fftwf_execute_dft_r2c(plans_->forward, time_buffer_, static_cast<fftwf_complex*>(spectrum_buffer_));
}

void RealFft::inverseInPlace() {
  fftwf_execute_dft_c2r(plans_->inverse, static_cast<fftwf_complex*>(spectrum_buffer_), time_buffer_);
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

struct ComplexInverseFft::Plan {
  fftwf_plan inverse = nullptr;
  ~Plan() {
    if (inverse) fftwf_destroy_plan(inverse);
  }
};

ComplexInverseFft::ComplexInverseFft(std::size_t size) : size_(size) {
  if (size == 0) throw std::invalid_argument("ComplexInverseFft size must be positive");
  in_ = fftwf_alloc_complex(size_);
  out_ = fftwf_alloc_complex(size_);
  if (!in_ || !out_) throw std::bad_alloc();
  plan_ = sharedPlans<Plan>(size_, [&] {
    auto plan = std::make_shared<Plan>();
    plan->inverse = fftwf_plan_dft_1d(static_cast<int>(size_), static_cast<fftwf_complex*>(in_),
                                      static_cast<fftwf_complex*>(out_), FFTW_BACKWARD, FFTW_ESTIMATE);
    if (!plan->inverse) throw std::runtime_error("FFTW could not plan");
    return plan;
  });
}

ComplexInverseFft::~ComplexInverseFft() {
  fftwf_free(in_);
  fftwf_free(out_);
}

void ComplexInverseFft::inverse(const std::complex<float>* spectrum, std::complex<float>* time) {
  std::memcpy(in_, static_cast<const void*>(spectrum), size_ * sizeof(fftwf_complex));
  fftwf_execute_dft(plan_->inverse, static_cast<fftwf_complex*>(in_), static_cast<fftwf_complex*>(out_));
  std::memcpy(static_cast<void*>(time), out_, size_ * sizeof(fftwf_complex));
}

}  // namespace room_reverb::core
