#include "room_reverb/binaural/loudspeaker_layout.h"

#include <cmath>
#include <sstream>

#include "room_reverb/common/directions.h"
#include "room_reverb/common/error.h"
#include "room_reverb/rsao/direction_of_arrival.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;

void appendRing(std::vector<Eigen::Vector3d>& layout, int count, double elevation_deg) {
  for (int i = 0; i < count; ++i) layout.push_back(unitVectorFromAngles(2.0 * kPi * i / count, elevation_deg * kDegree));
}

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

}  // namespace

std::vector<Eigen::Vector3d> paperRingsLayout() {
  std::vector<Eigen::Vector3d> layout;
  appendRing(layout, 24, 0.0);
  appendRing(layout, 12, 30.0);
  appendRing(layout, 12, -30.0);
  return layout;
}

std::vector<Eigen::Vector3d> fibonacciLayout(std::size_t count) {
  if (count < 21 || count > 10000) throw InputError("a fibonacci layout needs 21 to 10000 loudspeakers");
  // sphereGrid() makes ceil(4 pi / step^2) lattice points; this step asks for exactly
  // `count` with half a point of headroom against rounding.
  return sphereGrid(std::sqrt(4.0 * kPi / (static_cast<double>(count) - 0.5)));
}

std::vector<Eigen::Vector3d> loudspeakerLayoutByName(const std::string& name) {
  if (name == "paper_rings") return paperRingsLayout();
  const std::string prefix = "fibonacci_";
  if (name.rfind(prefix, 0) == 0 && name.size() > prefix.size() &&
      name.find_first_not_of("0123456789", prefix.size()) == std::string::npos && name.size() - prefix.size() <= 5) {
    return fibonacciLayout(std::stoul(name.substr(prefix.size())));
  }
  throw InputError("unknown loudspeaker layout '" + name +
                   "' (use paper_rings, fibonacci_<count> or a list 'az,el; az,el; ...' in degrees)");
}

std::vector<Eigen::Vector3d> loudspeakerLayoutFromDegrees(
    const std::vector<std::array<double, 2>>& azimuth_elevation_deg) {
  if (azimuth_elevation_deg.empty()) throw InputError("the loudspeaker layout is empty");
  std::vector<Eigen::Vector3d> layout;
  for (const auto& [azimuth, elevation] : azimuth_elevation_deg) {
    if (!std::isfinite(azimuth) || !std::isfinite(elevation)) throw InputError("loudspeaker angles must be finite");
    if (elevation < -90.0 || elevation > 90.0) {
      throw InputError("loudspeaker elevation " + std::to_string(elevation) + " deg is outside [-90, 90]");
    }
    const Eigen::Vector3d direction = unitVectorFromAngles(azimuth * kDegree, elevation * kDegree);
    for (const auto& other : layout) {
      if (direction.dot(other) > std::cos(0.1 * kDegree)) {
        throw InputError("two loudspeakers of the layout are less than 0.1 deg apart (near az " +
                         std::to_string(azimuth) + ", el " + std::to_string(elevation) + ")");
      }
    }
    layout.push_back(direction);
  }
  return layout;
}

std::vector<Eigen::Vector3d> parseLoudspeakerLayout(const std::string& text) {
  const std::string spec = trimmed(text);
  if (spec.empty()) throw InputError("the loudspeaker layout is empty");
  if (spec.find(',') == std::string::npos) return loudspeakerLayoutByName(spec);
  std::vector<std::array<double, 2>> angles;
  std::istringstream entries(spec);
  std::string entry;
  while (std::getline(entries, entry, ';')) {
    if (trimmed(entry).empty()) continue;
    std::istringstream pair(entry);
    std::array<double, 2> az_el{};
    char comma = 0;
    std::string rest;
    if (!(pair >> az_el[0] >> comma >> az_el[1]) || comma != ',' || (pair >> rest)) {
      throw InputError("cannot read loudspeaker '" + trimmed(entry) + "' (expected 'azimuth,elevation' in degrees)");
    }
    angles.push_back(az_el);
  }
  return loudspeakerLayoutFromDegrees(angles);
}

}  // namespace room_reverb::core
