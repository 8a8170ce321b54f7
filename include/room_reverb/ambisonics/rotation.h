#pragma once
// Rotation of AmbiX (ACN, SN3D, no Condon-Shortley phase) sound fields, for head tracking.
//
// A rotation maps the harmonics of each order l onto themselves, so its matrix is block
// diagonal with one (2l+1)-square block per order. Each block is found from its defining
// property Y_l(R d) = M_l Y_l(d) at a fixed set of directions D (more than 2l+1, spread
// over the sphere): M_l = Y_l(R D) Y_l(D)^+, with the pseudo-inverse computed once. This
// is exact (not a fit: the identity holds for every d, so for D), uses the project's own
// sn3dHarmonics() and therefore its conventions, and needs no per-order recursion.
//
// Frames (DESIGN.md, REP 103: x forward, y left, z up). A head-tracker orientation
// `head_in_room` is the rotation that takes head-frame vectors to room-frame vectors (the
// rotation of the room -> head transform, as a tf lookup of "head" in "room" gives it).
// A source at room direction d is at head direction head_in_room^-1 d, so the field heard
// by the listener is the room field rotated by the inverse: headTrackingRotation() does
// that. Example: the head turned 90 degrees to the left (yaw +pi/2 about z) hears a source
// on the room's left (+y) straight ahead (+x of the head).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

// The quaternion, normalised. A rotation quaternion read from a message or file may be off
// unit norm by rounding; one with a non-finite component or a norm off by more than
// kQuaternionNormTolerance is not a rotation and is an InputError ("malformed quaternion").
constexpr double kQuaternionNormTolerance = 1e-2;
Eigen::Quaterniond validatedRotation(const Eigen::Quaterniond& rotation);

// The ((order+1)^2)-square matrix M with sn3dHarmonics(order, R d) = M sn3dHarmonics(order, d)
// for every direction d: applied to a field (b' = M b) it moves a source at d to R d.
// Order 0..3. The matrix must be a proper rotation (orthonormal to 1e-6, determinant +1);
// otherwise, or for a malformed quaternion, InputError.
Eigen::MatrixXd ambisonicRotation(const Eigen::Matrix3d& rotation, int order);
Eigen::MatrixXd ambisonicRotation(const Eigen::Quaterniond& rotation, int order);

// The matrix that turns a room-frame field into the field the tracked listener hears:
// ambisonicRotation(head_in_room^-1, order). See the frame note above.
Eigen::MatrixXd headTrackingRotation(const Eigen::Quaterniond& head_in_room, int order);

// Applies a matrix from ambisonicRotation() to every frame of an AmbiX buffer in place.
// Only the per-order blocks are used (the rest of a rotation matrix is zero). The buffer
// must have as many channels as the matrix has rows, and the matrix be (order+1)^2 square
// for an order 0..3 (InputError otherwise). Allocates nothing.
void rotateAmbisonicBuffer(AudioBuffer& buffer, const Eigen::MatrixXd& rotation);

}  // namespace room_reverb::core
