#pragma once
// The diffuse-field covariance constraint of Zaunschirm, Schoerkhuber & Hoeldrich,
// "Binaural rendering of Ambisonic signals by head-related impulse response time
// alignment and a diffuseness constraint", JASA 143(6), 2018 (private to
// src/core/binaural).
//
// In a diffuse field the SN3D channels are uncorrelated with powers 1/(2l+1), so a
// decoder F (channels x 2 ears, at one frequency) gives the ears the covariance
// A = F^T diag(1/(2l+1)) conj(F), while the HRTF set itself gives
// T = sum_q w_q H_q^T conj(H_q) (H_q the 1 x 2 HRTF row of direction q, weights summing
// to one). Order truncation makes A too small at high frequencies (too dark) and its
// off-diagonal too large (too coherent, too narrow). A 2 x 2 mix K with K A K^H = T
// restores both; of all such mixes the one closest to the identity in the
// optimized-covariance sense of Vilkamo, Baeckstroem & Kuntz (J. AES 61(6), 2013) is
// K = L_T Q L_A^-1 with A = L_A L_A^H, T = L_T L_T^H (Cholesky) and the unitary
// Q = V U^H from the SVD L_A^H L_T = U S V^H. The corrected decoder is F K^T.
#include <Eigen/Core>

namespace room_reverb::core {

// The ears' diffuse-field covariance of `hrtfs` (directions x 2) under `weights`.
Eigen::Matrix2cd hrtfDiffuseFieldCovariance(const Eigen::MatrixXcd& hrtfs, const Eigen::VectorXd& weights);

// Applies the constraint to `decoder` (channels x 2) in place; `channel_powers` holds
// 1/(2l+1) per ACN channel. Leaves it as it is when either covariance is (near) singular.
void constrainDiffuseFieldCovariance(Eigen::MatrixXcd& decoder, const Eigen::Matrix2cd& target,
                                     const Eigen::VectorXd& channel_powers);

}  // namespace room_reverb::core
