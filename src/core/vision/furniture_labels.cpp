#include "furniture_labels.h"

namespace room_reverb::core::layout {

std::string furnitureLabel(const CuboidObject& box, bool floor_standing, bool against_wall) {
  const double length = box.size_m.x(), width = box.size_m.y();
  const double height = box.center_m.z() + 0.5 * box.size_m.z();
  if (!floor_standing) return against_wall ? "shelf" : "object";
  if (height >= 1.3) return width <= 0.4 ? "shelf" : "cabinet";
  if (height >= 0.3 && height < 0.65 && length >= 1.8 && width >= 0.9) return "bed";
  if (height >= 0.65 && height < 1.1 && length >= 1.4 && width >= 0.7) return "sofa";
  if (height >= 0.9) return length <= 0.7 ? "chair" : "cabinet";
  if (height >= 0.6) {
    if (length <= 0.7) return "chair";
    return against_wall && width <= 0.9 ? "desk" : "table";
  }
  if (height >= 0.3) {
    if (length >= 1.4 && width >= 0.6) return "sofa";
    return length <= 0.6 ? "box" : "table";
  }
  return "box";
}

}  // namespace room_reverb::core::layout
