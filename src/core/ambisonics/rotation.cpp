#include "room_reverb/ambisonics/rotation.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

// Directions where the harmonics are sampled: a Fibonacci spiral. 16 points make every
// order's block well conditioned (the spiral has no antipodal pairs, which would make the
// odd orders rank-deficient) while keeping the per-call cost at 16 harmonic evaluations.
constexpr int kSampleDirections = 16;

struct SampledHarmonics {
  Eigen::Matrix3Xd directions;
  // Per order l, the pseudo-inverse of Y_l(D): kSampleDirections x (2l+1).
  std::array<Eigen::MatrixXd, kMaxAmbisonicOrder + 1> pseudo_inverses;
};

const SampledHarmonics& sampledHarmonics() {
  static const SampledHarmonics sampled = [] {
    SampledHarmonics s;
    s.directions.resize(3, kSampleDirections);
    const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
    for (int k = 0; k < kSampleDirections; ++k) {
      const double z = 1.0 - (2.0 * k + 1.0) / kSampleDirections;
      const double r = std::sqrt(1.0 - z * z);
      s.directions.col(k) << r * std::cos(golden_angle * k), r * std::sin(golden_angle * k), z;
    }
    const int channels = ambisonicChannelCount(kMaxAmbisonicOrder);
    Eigen::MatrixXd y(channels, kSampleDirections);
    for (int k = 0; k < kSampleDirections; ++k) {
      const std::vector<double> h = sn3dHarmonics(kMaxAmbisonicOrder, s.directions.col(k));
      y.col(k) = Eigen::Map<const Eigen::VectorXd>(h.data(), channels);
    }
    for (int l = 0; l <= kMaxAmbisonicOrder; ++l) {
      const Eigen::MatrixXd block = y.middleRows(l * l, 2 * l + 1);
      // Y has full row rank, so its pseudo-inverse is Y^T (Y Y^T)^-1; Y Y^T is well
      // conditioned (condition number below 12 for these directions), so the normal
      // equations lose nothing that matters here.
      s.pseudo_inverses[l] = (block * block.transpose()).llt().solve(block).transpose();
    }
    return s;
  }();
  return sampled;
}

void checkOrder(int order) {
  if (order < 0 || order > kMaxAmbisonicOrder) {
    std::ostringstream os;
    os << "ambisonic order " << order << " is not supported; use 0 to " << kMaxAmbisonicOrder;
    throw InputError(os.str());
  }
}

// The order whose channel count is `channels`, or -1.
int orderOfChannelCount(Eigen::Index channels) {
  for (int order = 0; order <= kMaxAmbisonicOrder; ++order) {
    if (ambisonicChannelCount(order) == channels) return order;
  }
  return -1;
}

}  // namespace

Eigen::Quaterniond validatedRotation(const Eigen::Quaterniond& rotation) {
  const Eigen::Vector4d c = rotation.coeffs();
  if (!c.allFinite()) throw InputError("malformed quaternion: a component is not finite");
  const double norm = c.norm();
  if (std::abs(norm - 1.0) > kQuaternionNormTolerance) {
    std::ostringstream os;
    os << "malformed quaternion (x, y, z, w) = (" << c[0] << ", " << c[1] << ", " << c[2] << ", " << c[3]
       << "): norm " << norm << " is not 1; send a unit quaternion (identity is 0, 0, 0, 1)";
    throw InputError(os.str());
  }
  return Eigen::Quaterniond(c / norm);
}

Eigen::MatrixXd ambisonicRotation(const Eigen::Matrix3d& rotation, int order) {
  checkOrder(order);
  const double orthonormality_error = (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!rotation.allFinite() || orthonormality_error > 1e-6 || rotation.determinant() < 0.0) {
    throw InputError("rotation matrix is not a proper rotation (orthonormal with determinant +1)");
  }
  const SampledHarmonics& sampled = sampledHarmonics();
  const int channels = ambisonicChannelCount(order);
  Eigen::MatrixXd rotated(channels, kSampleDirections);  // Y(R D)
  for (int k = 0; k < kSampleDirections; ++k) {
    const std::vector<double> h = sn3dHarmonics(order, rotation * sampled.directions.col(k));
    rotated.col(k) = Eigen::Map<const Eigen::VectorXd>(h.data(), channels);
  }
  Eigen::MatrixXd matrix = Eigen::MatrixXd::Zero(channels, channels);
  for (int l = 0; l <= order; ++l) {
    matrix.block(l * l, l * l, 2 * l + 1, 2 * l + 1) = rotated.middleRows(l * l, 2 * l + 1) * sampled.pseudo_inverses[l];
  }
  return matrix;
}

Eigen::MatrixXd ambisonicRotation(const Eigen::Quaterniond& rotation, int order) {
  return ambisonicRotation(validatedRotation(rotation).toRotationMatrix(), order);
}

Eigen::MatrixXd headTrackingRotation(const Eigen::Quaterniond& head_in_room, int order) {
  return ambisonicRotation(validatedRotation(head_in_room).conjugate().toRotationMatrix(), order);
}

void rotateAmbisonicBuffer(AudioBuffer& buffer, const Eigen::MatrixXd& rotation) {
  const int order = orderOfChannelCount(rotation.rows());
  if (order < 0 || rotation.cols() != rotation.rows()) {
    std::ostringstream os;
    os << "ambisonic rotation matrix is " << rotation.rows() << " x " << rotation.cols()
       << "; it must be (order+1)^2 square for an order 0 to " << kMaxAmbisonicOrder;
    throw InputError(os.str());
  }
  if (buffer.channelCount() != static_cast<std::size_t>(rotation.rows())) {
    std::ostringstream os;
    os << "ambisonic buffer has " << buffer.channelCount() << " channels but the rotation is for order " << order
       << " (" << rotation.rows() << " channels)";
    throw InputError(os.str());
  }
  const std::size_t frames = buffer.frameCount();
  for (const auto& channel : buffer.channels) {
    if (channel.size() != frames) throw InputError("ambisonic buffer channels have different lengths");
  }
  // Frames in chunks through a stack copy, so the rotation runs in place without
  // allocating and the inner loop runs over contiguous samples.
  constexpr std::size_t kChunk = 64;
  constexpr int kMaxChannels = (kMaxAmbisonicOrder + 1) * (kMaxAmbisonicOrder + 1);
  float original[kMaxChannels][kChunk];
  for (std::size_t start = 0; start < frames; start += kChunk) {
    const std::size_t count = std::min(kChunk, frames - start);
    for (int c = 0; c < rotation.rows(); ++c) std::copy_n(&buffer.channels[c][start], count, original[c]);
    for (int l = 0; l <= order; ++l) {
      for (int row = l * l; row < (l + 1) * (l + 1); ++row) {
        float* out = &buffer.channels[row][start];
        std::fill_n(out, count, 0.0f);
        for (int col = l * l; col < (l + 1) * (l + 1); ++col) {
          const float gain = static_cast<float>(rotation(row, col));
          for (std::size_t n = 0; n < count; ++n) out[n] += gain * original[col][n];
        }
      }
    }
  }
}

}  // namespace room_reverb::core
