// The in-memory HRTF set: validation, nearest direction and time-aligned interpolation.
// Reading SOFA files is in hrtf_set_sofa.cpp.
#include "room_reverb/binaural/hrtf_set.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "hrir_timing.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

// Interpolation blends this many measured directions (a triangle around the target on a
// dense grid); one more is found to taper the weights (see interpolated()).
constexpr std::size_t kBlendedDirections = 3;
// Closer than this (radians, about 2e-7 degrees) a target is the measured direction itself.
constexpr double kSameDirectionRad = 1e-9;

std::string named(const std::string& description) {
  return description.empty() ? "HRTF set" : "HRTF set '" + description + "'";
}

bool allFinite(const std::vector<float>& samples) {
  return std::all_of(samples.begin(), samples.end(), [](float v) { return std::isfinite(v); });
}

void validate(double sample_rate_hz, const std::vector<Eigen::Vector3d>& directions,
              const std::vector<Hrir>& hrirs, const std::string& description) {
  const std::string what = named(description);
  if (!(sample_rate_hz >= kMinSampleRateHz && sample_rate_hz <= kMaxSampleRateHz)) {
    std::ostringstream os;
    os << what << ": sample rate " << sample_rate_hz << " Hz is outside " << kMinSampleRateHz
       << ".." << kMaxSampleRateHz << " Hz";
    throw InputError(os.str());
  }
  if (directions.empty()) throw InputError(what + " is empty: give at least one direction");
  if (hrirs.size() != directions.size()) {
    throw InputError(what + " has " + std::to_string(directions.size()) + " directions but " +
                     std::to_string(hrirs.size()) + " HRIRs: give one HRIR pair per direction");
  }
  const std::size_t length = hrirs.front().left.size();
  if (length == 0) throw InputError(what + " has empty HRIRs");
  for (std::size_t i = 0; i < hrirs.size(); ++i) {
    const std::string which = what + ", direction " + std::to_string(i);
    const Eigen::Vector3d& d = directions[i];
    if (!d.allFinite() || d.norm() == 0.0) {
      throw InputError(which + ": the direction is zero or not finite");
    }
    if (hrirs[i].left.size() != length || hrirs[i].right.size() != length) {
      throw InputError(which + ": HRIRs of " + std::to_string(hrirs[i].left.size()) + "/" +
                       std::to_string(hrirs[i].right.size()) + " samples where the set has " +
                       std::to_string(length) + ": every HRIR must have the same length");
    }
    if (!allFinite(hrirs[i].left) || !allFinite(hrirs[i].right)) {
      throw InputError(which + ": the HRIR contains NaN or infinite samples");
    }
  }
}

void requireDirection(const Eigen::Vector3d& direction, const char* what) {
  if (!direction.allFinite() || direction.norm() == 0.0) {
    throw InputError(std::string("cannot ") + what + " for a zero or non-finite direction");
  }
}

struct Neighbour {
  std::size_t index;
  double angle_rad;
};

// The `count` measured directions with the largest dot products (closest first), with
// their angles to `direction` (a unit vector).
std::vector<Neighbour> closest(const Eigen::MatrixX3d& rows,
                               const std::vector<Eigen::Vector3d>& directions,
                               const Eigen::Vector3d& direction, std::size_t count) {
  const Eigen::VectorXd dots = rows * direction;
  std::vector<std::size_t> order(static_cast<std::size_t>(dots.size()));
  std::iota(order.begin(), order.end(), std::size_t{0});
  count = std::min(count, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<long>(count), order.end(),
                    [&](std::size_t a, std::size_t b) {
                      return dots[static_cast<long>(a)] > dots[static_cast<long>(b)];
                    });
  std::vector<Neighbour> result;
  for (std::size_t k = 0; k < count; ++k) {
    const Eigen::Vector3d& d = directions[order[k]];
    // atan2 of |cross| and dot stays accurate for tiny angles, where acos(dot) does not.
    result.push_back({order[k], std::atan2(d.cross(direction).norm(), d.dot(direction))});
  }
  return result;
}

// Inverse-angular-distance weights, tapered so that the weight of a direction reaches
// zero just as it stops being one of the blended ones: w_i = 1/a_i - 1/a_next with a_next
// the angle of the first direction not blended (a modified Shepard weighting). Plain
// 1/a_i would jump whenever the set of neighbours changes as the target moves.
std::vector<double> blendWeights(const std::vector<Neighbour>& neighbours,
                                 std::size_t blended) {
  const double cutoff =
      neighbours.size() > blended ? 1.0 / neighbours[blended].angle_rad : 0.0;
  std::vector<double> weights;
  for (std::size_t k = 0; k < std::min(blended, neighbours.size()); ++k) {
    weights.push_back(std::max(0.0, 1.0 / neighbours[k].angle_rad - cutoff));
  }
  double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  if (total <= 0.0) {  // all equally far (e.g. the pole of a ring): share equally
    std::fill(weights.begin(), weights.end(), 1.0);
    total = static_cast<double>(weights.size());
  }
  for (double& w : weights) w /= total;
  return weights;
}

}  // namespace

HrtfSet::HrtfSet(double sample_rate_hz, std::vector<Eigen::Vector3d> directions,
                 std::vector<Hrir> hrirs, std::string description)
    : sample_rate_hz_(sample_rate_hz),
      directions_(std::move(directions)),
      hrirs_(std::move(hrirs)),
      description_(std::move(description)) {
  validate(sample_rate_hz_, directions_, hrirs_, description_);
  direction_rows_.resize(static_cast<long>(directions_.size()), 3);
  onsets_.reserve(directions_.size());
  for (std::size_t i = 0; i < directions_.size(); ++i) {
    directions_[i].normalize();
    direction_rows_.row(static_cast<long>(i)) = directions_[i].transpose();
    onsets_.push_back({hrir_timing::onsetSamples(hrirs_[i].left),
                       hrir_timing::onsetSamples(hrirs_[i].right)});
  }
}

std::size_t HrtfSet::nearest(const Eigen::Vector3d& direction) const {
  requireDirection(direction, "find the nearest HRTF");
  Eigen::Index best = 0;
  (direction_rows_ * direction).maxCoeff(&best);
  return static_cast<std::size_t>(best);
}

// Time-aligned interpolation. Averaging HRIRs as they are would add copies of the direct
// sound at slightly different delays (a comb filter, and an ITD that jumps rather than
// glides). So each blended HRIR is first moved to the weighted mean onset of its ear,
// then the moved HRIRs are averaged: the same as removing each onset, averaging and
// putting the interpolated onset back, with one fractional delay instead of two. The
// delays are linear phases in the frequency domain (hrir_timing::DelayingSum).
Hrir HrtfSet::interpolated(const Eigen::Vector3d& direction) const {
  requireDirection(direction, "interpolate the HRTF");
  const std::vector<Neighbour> neighbours =
      closest(direction_rows_, directions_, direction.normalized(), kBlendedDirections + 1);
  if (neighbours.front().angle_rad < kSameDirectionRad) return hrirs_[neighbours.front().index];

  const std::vector<double> weights = blendWeights(neighbours, kBlendedDirections);
  HrirOnset target{0.0, 0.0};
  for (std::size_t k = 0; k < weights.size(); ++k) {
    target.left += weights[k] * onsets_[neighbours[k].index].left;
    target.right += weights[k] * onsets_[neighbours[k].index].right;
  }
  hrir_timing::DelayingSum left(length(), length());
  hrir_timing::DelayingSum right(length(), length());
  for (std::size_t k = 0; k < weights.size(); ++k) {
    const std::size_t i = neighbours[k].index;
    left.add(hrirs_[i].left, weights[k], target.left - onsets_[i].left);
    right.add(hrirs_[i].right, weights[k], target.right - onsets_[i].right);
  }
  return {left.take(), right.take()};
}

}  // namespace room_reverb::core
