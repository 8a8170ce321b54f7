#include "room_reverb/common/quantile.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

double quantileLinear(std::vector<double> values, double q) {
  if (values.empty()) throw InputError("quantileLinear: no values");
  if (!(q >= 0.0 && q <= 1.0)) {
    std::ostringstream os;
    os << "quantileLinear: q = " << q << " is outside [0, 1]";
    throw InputError(os.str());
  }
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!std::isfinite(values[k])) {
      std::ostringstream os;
      os << "quantileLinear: value " << k << " is " << values[k];
      throw InputError(os.str());
    }
  }
  std::sort(values.begin(), values.end());
  const double position = q * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  if (below + 1 >= values.size()) return values.back();
  return values[below] + (position - static_cast<double>(below)) * (values[below + 1] - values[below]);
}

}  // namespace room_reverb::core
