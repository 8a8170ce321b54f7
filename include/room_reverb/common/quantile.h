#pragma once
// Sample quantiles, shared by the listening-test statistics and the box plots.
#include <vector>

namespace room_reverb::core {

// The q-quantile (q in [0, 1]) by linear interpolation between the sorted values, as
// numpy.quantile's default (Hyndman and Fan's type 7): position q * (n - 1) in the sorted
// order. InputError for no values, a non-finite value, or q outside [0, 1].
double quantileLinear(std::vector<double> values, double q);

}  // namespace room_reverb::core
