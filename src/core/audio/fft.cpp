#include "room_reverb/audio/fft.h"

#include <fftw3.h>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>

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

// The plans of one kind for `size` and `planning`, made by `make` (under the planner's
// lock) the first time and shared after. Plans are executed on other buffers of the same
// (fftwf_malloc) alignment.
template <typename PlanSet, typename Make>
std::shared_ptr<const PlanSet> sharedPlans(std::size_t size, FftPlanning planning, Make make) {
  std::lock_guard<std::mutex> lock(plannerMutex());
  static std::map<std::pair<std::size_t, FftPlanning>, std::shared_ptr<const PlanSet>> cache;
  auto found = cache.find({size, planning});
  if (found != cache.end()) return found->second;
  std::shared_ptr<const PlanSet> plans = make();
  cache.emplace(std::make_pair(size, planning), plans);
  return plans;
}

// Where measured plans are kept between processes (fft.h), or "" for nowhere.
std::string wisdomPath() {
  if (const char* path = std::getenv("ROOM_REVERB_FFTW_WISDOM")) return path;
  if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache && *cache) {
    return std::string(cache) + "/room_reverb/fftwf.wisdom";
  }
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/room_reverb/fftwf.wisdom";
  return "";
}

// Makes measured plans by `plan` (under the planner's lock) from the wisdom kept on disk,
// saves what was measured, and forgets it all again: an estimated plan made later in this
// process must not inherit a measured choice (FFTW's estimate planner uses any wisdom it
// holds), or the same transform would round differently in different processes.
template <typename Plan>
void withKeptWisdom(Plan plan) {
  const std::string path = wisdomPath();
  if (!path.empty()) fftwf_import_wisdom_from_filename(path.c_str());  // absent or unreadable: measured afresh
  plan();
  if (!path.empty()) {
    // By rename, so that processes saving at once never leave half a file.
    std::error_code ignored;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ignored);
    const std::string partial = path + "." + std::to_string(::getpid()) + ".partial";
    if (fftwf_export_wisdom_to_filename(partial.c_str()) != 0) {
      std::filesystem::rename(partial, path, ignored);
    }
    std::filesystem::remove(partial, ignored);
  }
  fftwf_forget_wisdom();
}

}  // namespace

RealFft::RealFft(std::size_t size, FftPlanning planning) : size_(size) {
  if (size == 0) throw std::invalid_argument("RealFft size must be positive");
  time_buffer_ = fftwf_alloc_real(size_);
  spectrum_buffer_ = fftwf_alloc_complex(spectrumSize());
  if (!time_buffer_ || !spectrum_buffer_) throw std::bad_alloc();
  plans_ = sharedPlans<Plans>(size_, planning, [&] {
    auto plans = std::make_shared<Plans>();
    auto* spectrum = static_cast<fftwf_complex*>(spectrum_buffer_);
    const int n = static_cast<int>(size_);
    const auto make = [&](unsigned flags) {
      plans->forward = fftwf_plan_dft_r2c_1d(n, time_buffer_, spectrum, flags);
      plans->inverse = fftwf_plan_dft_c2r_1d(n, spectrum, time_buffer_, flags);
    };
    if (planning == FftPlanning::kMeasured) {
      withKeptWisdom([&] { make(FFTW_MEASURE); });
    } else {
      make(FFTW_ESTIMATE);
    }
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
  plan_ = sharedPlans<Plan>(size_, FftPlanning::kEstimate, [&] {
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

void prepareMeasuredFftPlans(std::size_t smallest, std::size_t largest) {
  for (std::size_t size = std::max<std::size_t>(smallest, 1); size <= largest; size *= 2) {
    const RealFft plans(size, FftPlanning::kMeasured);  // kept in the shared plan cache
  }
}

}  // namespace room_reverb::core
