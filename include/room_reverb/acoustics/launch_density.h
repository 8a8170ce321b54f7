#pragma once
// Importance sampling of the rays' launch directions.
//
// In a room whose absorption sits on a few surfaces and whose walls scatter little, the
// late decay is carried by the rays that leave in a few directions (those that graze the
// absorbing floor and ceiling run between the hard walls for seconds), and a run of
// uniformly launched rays holds few of them: its estimate of the late energy is heavy-
// tailed, and a finite run reads the decay short (docs/simulation.md: the classroom's
// 125 Hz T20 10 % short at 57 000 rays against 100 000-400 000). Launching more rays in
// those directions, each carrying its share of the emission times the uniform density
// over the density it was drawn from, keeps every estimate unbiased (the expected energy
// of every path is unchanged) and spends the rays where the late energy is.
//
// The sphere is cut into equal-area cells in the room frame: kLaunchZones zones of equal
// height in z (the room's vertical, where floors and ceilings absorb) times
// kLaunchSectors sectors of azimuth. A density gives each cell a probability; within a
// cell the direction is uniform.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace room_reverb::core {

constexpr int kLaunchZones = 64;
constexpr int kLaunchSectors = 4;
constexpr int kLaunchCells = kLaunchZones * kLaunchSectors;

// The cell of a unit direction (room frame): zone (from z = 1 down) times kLaunchSectors
// plus sector (azimuth counter-clockwise from +x).
int launchCellOf(const Eigen::Vector3d& direction);

class LaunchDensity {
 public:
  // Uniform: every cell 1 / kLaunchCells.
  LaunchDensity();
  // Per cell, each positive and finite; normalised to sum 1. InputError otherwise.
  explicit LaunchDensity(const std::array<double, kLaunchCells>& cell_weights);
  // Exactly these probabilities (another density's, as the wire carries them): each
  // positive, summing to 1 within 1e-9. InputError otherwise.
  static LaunchDensity fromProbabilities(const std::array<double, kLaunchCells>& probabilities);

  struct Draw {
    Eigen::Vector3d direction;  // unit, room frame
    double weight = 1.0;        // the uniform density over this one at `direction`
  };
  // The direction whose zone position is `u` and whose azimuth position within its zone
  // is `v`, both in [0, 1): u runs through the zones by their probabilities (a ray's
  // stratified fraction (index + jitter) / count keeps the rays stratified), v through the
  // zone's sectors by theirs. u and v uniform give directions of this density.
  Draw draw(double u, double v) const;

  const std::array<double, kLaunchCells>& probabilities() const { return probability_; }

 private:
  void buildZones();

  std::array<double, kLaunchCells> probability_{};
  std::array<double, kLaunchZones + 1> zone_cdf_{};  // cumulative over zones
};

// The density a pilot's late energy asks for: `mixture` of it follows each cell's share of
// the late energy (`late_share`, summing to 1; the mean of the bands' shares), the rest is
// uniform, so that no cell's rays weigh more than 1 / (1 - mixture) of a uniform ray's
// (Hesterberg's defensive mixture: the early energy, spread over every direction, keeps
// its estimate). InputError for a mixture outside [0, 1) or shares that are negative or
// do not sum to 1 within 1e-6.
LaunchDensity lateEnergyDensity(const std::array<double, kLaunchCells>& late_share, double mixture);

}  // namespace room_reverb::core
