#pragma once
// The sample mean and standard deviation, shared by the diagnosis's noise and seed gains,
// the listening-test statistics, and the benches and tests that measure spreads.
#include <vector>

namespace room_reverb::core {

// InputError for no values.
double sampleMean(const std::vector<double>& values);
// With Bessel's correction (n - 1); InputError for fewer than two values.
double sampleStandardDeviation(const std::vector<double>& values);

}  // namespace room_reverb::core
