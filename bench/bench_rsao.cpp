// Speed of the RSAO estimator (target: a 1 s, 4-channel, 48 kHz RIR parameterised in
// under 10 ms median on one core), whole and by stage, on the first second of a bundled
// measured RIR. Run: scripts/bench (or .ws/devel/lib/room_reverb/bench_rsao).
#include <benchmark/benchmark.h>

#include <string>

#include "room_reverb/ambisonics/bformat.h"
#include "room_reverb/audio/audio_file.h"
#include "room_reverb/rsao/early_reflections.h"
#include "room_reverb/rsao/echo_density.h"
#include "room_reverb/rsao/late_reverb.h"
#include "room_reverb/rsao/rsao_estimator.h"
#include "room_reverb/rsao/rsao_resynthesis.h"

namespace {

using namespace room_reverb::core;

// The Dixon studio theatre (T60 about 1 s), cut to 1 s: the case.
const AudioBuffer& oneSecondRir() {
  static const AudioBuffer rir = [] {
    AudioBuffer b = toAmbix(readAudioFile(std::string(ROOM_REVERB_SOURCE_DIR) +
                                          "/data/rirs/bformat/dixon_studio_theatre_r1.wav"),
                            AmbisonicFormat::kFuMa);
    for (auto& channel : b.channels) channel.resize(48000);
    return b;
  }();
  return rir;
}

// fit_onset: the fitted early course (0: the paper's ramp); two_slopes: bent late decays
// (0: one slope per band); matched: the early reflections by matching pursuit (0: the
// paper's group-delay onsets). 1/1/1 is the default; 0/0/0 the paper's estimator.
void BM_EstimateRsao1s(benchmark::State& state) {
  RsaoOptions options;
  options.fit_onset_ramps = state.range(0) != 0;
  options.late.two_slopes = state.range(1) != 0;
  options.early.onset_method = state.range(2) != 0 ? OnsetMethod::kMatchedPursuit : OnsetMethod::kGroupDelay;
  for (auto _ : state) benchmark::DoNotOptimize(estimateRsao(oneSecondRir(), AmbisonicFormat::kAmbiX, options));
}
BENCHMARK(BM_EstimateRsao1s)
    ->ArgNames({"fit_onset", "two_slopes", "matched"})
    ->Args({1, 1, 1})
    ->Args({1, 1, 0})
    ->Args({1, 0, 1})
    ->Args({0, 0, 0})
    ->Unit(benchmark::kMillisecond);

void BM_MixingTime1s(benchmark::State& state) {
  const auto& w = oneSecondRir().channels[kAcnW];
  for (auto _ : state) benchmark::DoNotOptimize(estimateMixingTime(echoDensityProfile(w, 48000.0), 0.005));
}
BENCHMARK(BM_MixingTime1s)->Unit(benchmark::kMillisecond);

// matched: matching pursuit (the default); 0: the paper's group-delay onsets.
void BM_EarlyReflections1s(benchmark::State& state) {
  EarlyReflectionOptions options;
  options.mixing_time_s = 0.03;
  options.onset_method = state.range(0) != 0 ? OnsetMethod::kMatchedPursuit : OnsetMethod::kGroupDelay;
  for (auto _ : state) benchmark::DoNotOptimize(estimateEarlyReflections(oneSecondRir(), options));
}
BENCHMARK(BM_EarlyReflections1s)->ArgName("matched")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// two_slopes:0 is the paper's one decay per band; 1 adds the bent-decay fit where a band
// bends (late_reverb.h).
void BM_LateReverb1s(benchmark::State& state) {
  const auto& w = oneSecondRir().channels[kAcnW];
  LateReverbOptions options;
  options.two_slopes = state.range(0) != 0;
  for (auto _ : state) benchmark::DoNotOptimize(estimateLateReverb(w, 0.007, 0.03, options));
}
BENCHMARK(BM_LateReverb1s)->ArgName("two_slopes")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

void BM_Resynthesis1s(benchmark::State& state) {
  const Rsao rsao = estimateRsao(oneSecondRir(), AmbisonicFormat::kAmbiX);
  for (auto _ : state) benchmark::DoNotOptimize(resynthesizeRsao(rsao));
}
BENCHMARK(BM_Resynthesis1s)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
