#include <gtest/gtest.h>

#include "room_reverb/common/error.h"
#include "room_reverb/metrics/onset.h"
#include "synthetic_rir.h"

using namespace room_reverb::core;

TEST(Onset, DelayedImpulseIsExactToTheSample) {
  for (std::size_t delay : {0u, 1u, 480u, 12345u}) {
    std::vector<float> rir = room_reverb::test::exponentialDecayNoise(20000, 0.5, delay + 1, 3);
    for (auto& v : rir) v *= 0.05f;  // reverberation well below the direct sound
    rir[delay] = 1.0f;
    EXPECT_EQ(findDirectSoundOnset(rir), delay);
  }
}

TEST(Onset, FirstSampleWithin20dBOfThePeak) {
  std::vector<float> rir(1000, 0.0f);
  rir[100] = 0.099f;  // -20.09 dB: below the threshold
  rir[200] = 0.101f;  // -19.91 dB: the onset
  rir[300] = 1.0f;
  EXPECT_EQ(findDirectSoundOnset(rir), 200u);
  EXPECT_EQ(findDirectSoundOnset(rir, 30.0), 100u);
}

TEST(Onset, SilenceIsAClearError) {
  EXPECT_THROW(findDirectSoundOnset(std::vector<float>(100, 0.0f)), InputError);
  EXPECT_THROW(findDirectSoundOnset({}), InputError);
}
