#include "room_reverb/vision/oriented_box_iou.h"

#include <algorithm>
#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

namespace {

void checkBox(const CuboidObject& box, const char* which) {
  if (!box.center_m.allFinite() || !box.size_m.allFinite() || !std::isfinite(box.yaw_rad)) {
    throw InputError(std::string("orientedBoxIoU3d: box ") + which + " has a non-finite centre, size or yaw");
  }
  if ((box.size_m.array() < 0.0).any()) {
    throw InputError(std::string("orientedBoxIoU3d: box ") + which + " has a negative size");
  }
}

}  // namespace

double orientedBoxIoU3d(const CuboidObject& a, const CuboidObject& b) {
  checkBox(a, "a");
  checkBox(b, "b");
  const double volume_a = a.size_m.prod();
  const double volume_b = b.size_m.prod();
  if (volume_a + volume_b <= 0.0) return 0.0;
  const double intersection = cuboidOverlapM3(a, b);
  if (intersection <= 0.0) return 0.0;
  const double union_volume = volume_a + volume_b - intersection;
  if (union_volume <= 0.0) return 0.0;
  // Rounding in the clipping may push a perfect overlap a hair past 1.
  return std::clamp(intersection / union_volume, 0.0, 1.0);
}

}  // namespace room_reverb::core
