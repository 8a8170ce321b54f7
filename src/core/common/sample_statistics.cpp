#include "room_reverb/common/sample_statistics.h"

#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

double sampleMean(const std::vector<double>& values) {
  if (values.empty()) throw InputError("no values to average");
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

double sampleStandardDeviation(const std::vector<double>& values) {
  if (values.size() < 2) throw InputError("a standard deviation needs at least two values");
  const double mean = sampleMean(values);
  double sum_sq = 0.0;
  for (double v : values) sum_sq += (v - mean) * (v - mean);
  return std::sqrt(sum_sq / static_cast<double>(values.size() - 1));
}

}  // namespace room_reverb::core
