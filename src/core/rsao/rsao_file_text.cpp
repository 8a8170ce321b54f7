#include "rsao_file_text.h"

#include <charconv>
#include <cmath>

namespace room_reverb::core::rsao_text {
namespace {

constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;
constexpr int kSearchUlps = 64;

// Among the doubles near radians / (pi/180), the one whose conversion back lands nearest
// `radians`; ties go to the first in the order d, d+, d-, d++, d--, ...
double nearestPreimage(double radians) {
  const double start = radians / kRadiansPerDegree;
  double best = start, best_error = std::abs(radiansFromFileDegrees(start) - radians);
  double up = start, down = start;
  for (int i = 0; i < kSearchUlps && best_error > 0.0; ++i) {
    up = std::nextafter(up, HUGE_VAL);
    down = std::nextafter(down, -HUGE_VAL);
    for (double candidate : {up, down}) {
      const double error = std::abs(radiansFromFileDegrees(candidate) - radians);
      if (error < best_error) {
        best = candidate;
        best_error = error;
      }
    }
  }
  return best;
}

}  // namespace

std::string shortestDecimal(double value) {
  if (std::isnan(value)) return ".nan";
  if (std::isinf(value)) return value > 0 ? ".inf" : "-.inf";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

double radiansFromFileDegrees(double degrees) { return degrees * kRadiansPerDegree; }

double fileDegrees(double radians) {
  if (!std::isfinite(radians)) return radians / kRadiansPerDegree;
  // Step 1 lands on radians some degrees reach exactly; step 2 picks, for those radians,
  // the degrees step 1 would pick again, so a second round trip changes nothing.
  const double settled = radiansFromFileDegrees(nearestPreimage(radians));
  return nearestPreimage(settled);
}

}  // namespace room_reverb::core::rsao_text
