#pragma once
// The direct sound and early reflections of an RSAO for a listener who moves, as taps on
// one delay line of the source: each tap reads the source at its time of arrival (cubic
// Lagrange interpolation between samples), shapes it with its reflection's filter (the
// RSAO's second-order sections, their state kept from block to block), scales it and
// encodes it into the ambisonic field in its direction. Delay, amplitude and encoding
// gains move linearly, sample by sample, from the previous block's values to the new
// ones, so a walking listener hears no steps, clicks or zipper noise: a delay that glides
// is a small Doppler shift, as it is in the room. A reflection that stops being heard
// fades out over one block and one that starts fades in.
//
// The scale matches the RSAO: a tap's energy under the estimator's window is its level
// squared, as resynthesizeRsao places it (reflection_tap.h).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

struct ReflectionTapBankOptions {
  int order = 3;                    // ambisonic order of the field the taps are added to
  std::size_t block_size = 256;     // frames per process() call
  double max_delay_s = 0.5;         // longest time of arrival a tap can read (longer: clamped)
  double analysis_window_s = 0.002; // the estimator's level window (EarlyReflectionOptions)
};

// One tap's target for the next block.
struct TapTarget {
  double delay_s = 0.0;                                  // time of arrival
  double level = 0.0;                                    // EarlyReflection::level; 0: silent
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit, in the field's frame
  // A one-pole low-pass after the tap's own filter, y[n] = (1 - p) x[n] + p y[n-1], p in
  // [0, 1): the direct sound behind an object, duller as well as weaker
  // (ListenerTranslation). 0: none.
  double lowpass_pole = 0.0;
};

class ReflectionTapBank {
 public:
  // One tap per reflection, its filter and level scale from `reflections` (their times,
  // levels and directions are the targets'). Taps start silent. Throws InputError for
  // bad options or an unstable reflection filter.
  ReflectionTapBank(const std::vector<EarlyReflection>& reflections, const ReflectionTapBankOptions& options);

  std::size_t size() const { return taps_.size(); }
  std::size_t channels() const { return channels_; }

  // The targets for the next block, one per tap in the constructor's order; a non-finite
  // target, or one with a low-pass pole outside [0, 1), keeps the tap's previous one. Throws InputError for a count that differs.
  void setTargets(const std::vector<TapTarget>& targets);

  // Every tap fades out over the next block (a bank being replaced).
  void fadeOut();

  // Adds one block of the taps, fed by `source` (block_size samples), into `field`
  // (channels() pointers to block_size samples each).
  void process(const float* source, float* const* field);

  // Taps whose delay was clamped to max_delay_s, since construction.
  std::size_t clampedTargets() const { return clamped_targets_; }

 private:
  struct Tap {
    double unit_gain = 0.0;  // the shape's scale per unit level
    double delay_from = 0.0, delay_to = 0.0;  // samples
    double amplitude_from = 0.0, amplitude_to = 0.0;
    std::vector<double> gains_from, gains_to;  // encoding gains, channels_
  };

  // Tap k's read of the source for this block into lane k of samples_.
  void readTap(std::size_t k, std::size_t block_start);
  // Restarts tap k's filter from rest.
  void clearFilterState(std::size_t k);

  ReflectionTapBankOptions options_;
  std::size_t channels_ = 0;
  std::vector<Tap> taps_;
  // The taps' filters side by side (tap_kernels.h): section s of tap k at s * lanes_ + k;
  // lanes_ is the tap count rounded up to whole SIMD vectors, a tap with fewer sections
  // and the spare lanes pass their input through (b0 = 1). The last section is every
  // tap's low-pass (TapTarget::lowpass_pole), run only while one of them is set and for
  // the block after (its state, p y, then empties).
  std::size_t lanes_ = 0, sections_ = 0;
  bool lowpass_running_ = false, lowpass_set_ = false;
  std::vector<float> b0_, b1_, b2_, a1_, a2_, s1_, s2_;
  std::vector<float> samples_;  // the block's tap signals, tap k's sample n at k * block_size + n
  std::vector<float> lane_scratch_;  // the same, sample-major, for the filters
  std::vector<float> history_;  // the source, a ring of history_size_ samples, stored twice
  std::size_t history_size_ = 0;
  std::size_t write_ = 0;       // where the next source sample goes
  std::vector<float> tap_signal_;                 // the heard taps' scaled signals, one block each
  std::vector<float> gains_from_, gains_change_;  // their encoding glides, channels_ each
  std::vector<float> ramp_;  // (n + 1) / block_size: the glide's weight at sample n
  std::size_t clamped_targets_ = 0;
};

}  // namespace room_reverb::core
