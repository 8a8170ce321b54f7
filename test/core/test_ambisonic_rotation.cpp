#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "room_reverb/ambisonics/rotation.h"
#include "room_reverb/ambisonics/spherical_harmonics.h"
#include "room_reverb/common/error.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;

namespace {

Eigen::VectorXd harmonics(int order, const Eigen::Vector3d& direction) {
  const auto h = sn3dHarmonics(order, direction);
  return Eigen::Map<const Eigen::VectorXd>(h.data(), static_cast<Eigen::Index>(h.size()));
}

Eigen::Vector3d randomDirection(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
}

Eigen::Quaterniond randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  return Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized();
}

Eigen::Quaterniond yaw(double angle) { return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ())); }

}  // namespace

TEST(AmbisonicRotation, RotatesPlaneWavesToTheRotatedDirection) {
  std::mt19937 rng(1);
  for (int order = 1; order <= 3; ++order) {
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::Quaterniond q = randomRotation(rng);
      const Eigen::Vector3d d = randomDirection(rng);
      const Eigen::MatrixXd m = ambisonicRotation(q, order);
      ASSERT_EQ(m.rows(), ambisonicChannelCount(order));
      EXPECT_LT((m * harmonics(order, d) - harmonics(order, q * d)).cwiseAbs().maxCoeff(), 1e-9)
          << "order " << order << " trial " << trial;
      // The Matrix3d overload is the same rotation.
      EXPECT_LT((ambisonicRotation(q.toRotationMatrix(), order) - m).cwiseAbs().maxCoeff(), 1e-12);
    }
  }
}

TEST(AmbisonicRotation, IdentityAndComposition) {
  std::mt19937 rng(2);
  for (int order = 0; order <= 3; ++order) {
    const int n = ambisonicChannelCount(order);
    EXPECT_LT((ambisonicRotation(Eigen::Quaterniond::Identity(), order) - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff(), 1e-12);
    const Eigen::Quaterniond a = randomRotation(rng);
    const Eigen::Quaterniond b = randomRotation(rng);
    const Eigen::MatrixXd composed = ambisonicRotation(a, order) * ambisonicRotation(b, order);
    EXPECT_LT((ambisonicRotation(a * b, order) - composed).cwiseAbs().maxCoeff(), 1e-10) << order;
    // A rotation keeps the SN3D energy of each order: the per-order blocks are orthogonal
    // under SN3D too (SN3D and N3D differ by one factor per order), so M^T M = I.
    const Eigen::MatrixXd m = ambisonicRotation(a, order);
    EXPECT_LT((m.transpose() * m - Eigen::MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff(), 1e-10) << order;
  }
}

TEST(AmbisonicRotation, HeadTurnedLeftHearsTheLeftSourceInFront) {
  // Head yawed +90 degrees (turned to its left, z up): a source on the room's left (+y)
  // is straight ahead of the listener (+x of the head frame).
  const Eigen::VectorXd room_field = harmonics(3, Eigen::Vector3d::UnitY());
  const Eigen::VectorXd heard = headTrackingRotation(yaw(M_PI / 2), 3) * room_field;
  EXPECT_LT((heard - harmonics(3, Eigen::Vector3d::UnitX())).cwiseAbs().maxCoeff(), 1e-9);
  // First order spelled out (ACN W, Y, Z, X): all of the dipole energy moved from Y to X.
  EXPECT_NEAR(heard[1], 0.0, 1e-12);
  EXPECT_NEAR(heard[3], 1.0, 1e-12);
  // And it is the inverse of rotating the field by the head orientation.
  EXPECT_LT((headTrackingRotation(yaw(0.4), 2) - ambisonicRotation(yaw(-0.4), 2)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(AmbisonicRotation, RotatesABufferInPlace) {
  std::mt19937 rng(3);
  const Eigen::Vector3d d = randomDirection(rng);
  const Eigen::Quaterniond q = randomRotation(rng);
  const Eigen::VectorXd from = harmonics(3, d);
  const Eigen::VectorXd to = harmonics(3, q * d);
  // A plane wave carrying a ramp, longer than one internal chunk and not a multiple of it.
  AudioBuffer buffer = makeSilentBuffer(16, 150, 48000.0);
  for (int c = 0; c < 16; ++c) {
    for (std::size_t n = 0; n < 150; ++n) buffer.channels[c][n] = static_cast<float>(from[c] * (n + 1) / 150.0);
  }
  rotateAmbisonicBuffer(buffer, ambisonicRotation(q, 3));
  for (int c = 0; c < 16; ++c) {
    for (std::size_t n = 0; n < 150; ++n) ASSERT_NEAR(buffer.channels[c][n], to[c] * (n + 1) / 150.0, 1e-5) << c << " " << n;
  }
}

TEST(AmbisonicRotation, NormalisesSlightlyOffQuaternionsAndRejectsMalformedOnes) {
  const Eigen::Quaterniond almost(1.003 * Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())).coeffs());
  EXPECT_NEAR(validatedRotation(almost).norm(), 1.0, 1e-15);
  EXPECT_LT((ambisonicRotation(almost, 1) - ambisonicRotation(almost.normalized(), 1)).cwiseAbs().maxCoeff(), 1e-12);

  expectInputError([] { validatedRotation(Eigen::Quaterniond(0, 0, 0, 0)); }, {"malformed quaternion", "norm 0"});
  expectInputError([] { headTrackingRotation(Eigen::Quaterniond(2, 0, 0, 0), 1); }, {"malformed quaternion"});
  expectInputError([] { ambisonicRotation(Eigen::Quaterniond(NAN, 0, 0, 1), 1); }, {"malformed quaternion", "not finite"});
  expectInputError([] { ambisonicRotation(Eigen::Matrix3d(Eigen::Vector3d(1, 1, -1).asDiagonal()), 1); }, {"not a proper rotation"});
  expectInputError([] { ambisonicRotation(Eigen::Matrix3d(2.0 * Eigen::Matrix3d::Identity()), 1); }, {"not a proper rotation"});
  expectInputError([] { ambisonicRotation(Eigen::Quaterniond::Identity(), 4); }, {"order 4", "0 to 3"});

  AudioBuffer first_order = makeSilentBuffer(4, 8, 48000.0);
  expectInputError([&] { rotateAmbisonicBuffer(first_order, ambisonicRotation(yaw(1.0), 3)); }, {"4 channels", "order 3"});
  expectInputError([&] { rotateAmbisonicBuffer(first_order, Eigen::MatrixXd::Identity(5, 5)); }, {"5 x 5"});
}

// The in-place harmonics are the harmonics (first order in ACN/SN3D: 1, y, z, x), written
// into the caller's vector without reallocating it once it has the size.
TEST(SphericalHarmonics, IntoTheCallersVectorWithoutReallocating) {
  std::mt19937 rng(17);
  std::vector<double> y;
  sn3dHarmonicsInto(3, Eigen::Vector3d::UnitX(), y);
  ASSERT_EQ(y.size(), 16u);
  const double* storage = y.data();
  for (int k = 0; k < 50; ++k) {
    const Eigen::Vector3d d = randomDirection(rng);
    sn3dHarmonicsInto(3, d, y);
    EXPECT_EQ(y.data(), storage);
    EXPECT_EQ(y, sn3dHarmonics(3, d));
    EXPECT_NEAR(y[0], 1.0, 1e-15);
    EXPECT_NEAR(y[1], d.y(), 1e-12);
    EXPECT_NEAR(y[2], d.z(), 1e-12);
    EXPECT_NEAR(y[3], d.x(), 1e-12);
  }
  sn3dHarmonicsInto(1, Eigen::Vector3d::UnitZ(), y);
  EXPECT_EQ(y, (std::vector<double>{1.0, 0.0, 1.0, 0.0}));
  EXPECT_THROW(sn3dHarmonicsInto(4, Eigen::Vector3d::UnitZ(), y), InputError);
}
