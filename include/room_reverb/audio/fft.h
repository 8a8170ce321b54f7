#pragma once
// Real FFT and complex inverse FFT over FFTW3 (single precision). Plans are made once per
// size (and planning) and shared by every transform of that kind and size (FFTW's planner is not
// thread-safe, its execution is), so constructing one after the first of its size costs
// only its buffer allocations.
#include <complex>
#include <cstddef>
#include <memory>
#include <vector>

namespace room_reverb::core {

// Smallest n' >= n of the form 2^a 3^b 5^c 7^d, the sizes FFTW handles fastest.
std::size_t nextFastFftSize(std::size_t n);

// How a plan is chosen. kEstimate: by FFTW's heuristics, at once, the same on every
// machine. kMeasured: the fastest of FFTW's candidates timed on this machine
// (FFTW_MEASURE), for the streaming convolver's transforms, run every block: they take 7 %
// (512-4096 points, a Xeon) and 2-5 % more (32 768, an AMD EPYC) off a walking binaural
// stream (bench_binaural_renderer) and cost 0.15-1 s of planning per size. The measured
// choice is kept as FFTW wisdom in $ROOM_REVERB_FFTW_WISDOM (default
// $XDG_CACHE_HOME/room_reverb/fftwf.wisdom, or ~/.cache/room_reverb/fftwf.wisdom; an empty
// value keeps nothing), so a size is measured once per machine; the wisdom is forgotten
// again after each measured plan, so estimated plans never pick it up and stay the same
// in every process.
enum class FftPlanning { kEstimate, kMeasured };

class RealFft {
 public:
  explicit RealFft(std::size_t size, FftPlanning planning = FftPlanning::kEstimate);
  ~RealFft();
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;

  std::size_t size() const { return size_; }
  std::size_t spectrumSize() const { return size_ / 2 + 1; }

  // time: size() samples -> spectrum: spectrumSize() bins, unnormalised.
  void forward(const float* time, std::complex<float>* spectrum);
  // spectrum: spectrumSize() bins -> time: size() samples, scaled by 1/size() so that
  // inverse(forward(x)) == x.
  void inverse(const std::complex<float>* spectrum, float* time);

  std::vector<std::complex<float>> forward(const std::vector<float>& time);
  std::vector<float> inverse(const std::vector<std::complex<float>>& spectrum);

  // The transform's own buffers, for a caller that fills the input and reads the output
  // where they are (the streaming convolver: each copy around a 512-point transform costs
  // a sizeable part of the transform): timeData() holds size() samples, spectrumData()
  // spectrumSize() bins. forwardInPlace() transforms timeData() into spectrumData();
  // inverseInPlace() the other way, unnormalised (size() times inverse()'s result).
  float* timeData() { return time_buffer_; }
  std::complex<float>* spectrumData() { return static_cast<std::complex<float>*>(spectrum_buffer_); }
  void forwardInPlace();
  void inverseInPlace();

 private:
  struct Plans;
  std::size_t size_;
  std::shared_ptr<const Plans> plans_;
  float* time_buffer_;
  void* spectrum_buffer_;  // fftwf_complex*, kept opaque so FFTW stays out of this header
};

// Complex inverse FFT, for band signals taken down to baseband (BandFilterBank's energy
// envelopes): only the band's bins are transformed, at a rate set by its width.
class ComplexInverseFft {
 public:
  explicit ComplexInverseFft(std::size_t size);
  ~ComplexInverseFft();
  ComplexInverseFft(const ComplexInverseFft&) = delete;
  ComplexInverseFft& operator=(const ComplexInverseFft&) = delete;

  std::size_t size() const { return size_; }
  // spectrum: size() bins -> time: size() samples, unnormalised (sum_k X_k e^{+2 pi i k n / N}).
  void inverse(const std::complex<float>* spectrum, std::complex<float>* time);

 private:
  struct Plan;
  std::size_t size_;
  std::shared_ptr<const Plan> plan_;
  void* in_;   // fftwf_complex*
  void* out_;  // fftwf_complex*
};

// Makes the measured plans of every power-of-two real transform from `smallest` to
// `largest` points now (from the kept wisdom, or measured: about 1.5 s for 512-32 768 at a
// machine's first start). A real-time stream calls it before its audio thread starts: a
// plan is made under FFTW's one planner lock, and an audio thread that needs any plan
// while another thread measures one waits for it (without this, a renderer drops about 90
// chunks, 1 s of sound, when its first room arrives on a machine without kept wisdom).
void prepareMeasuredFftPlans(std::size_t smallest, std::size_t largest);

}  // namespace room_reverb::core
