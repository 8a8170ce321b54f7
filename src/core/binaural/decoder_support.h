#pragma once
// Pieces the binaural decoders share (private to src/core/binaural).
#include <Eigen/Core>
#include <complex>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "room_reverb/binaural/hrtf_set.h"

namespace room_reverb::core::decoder_support {

// InputError unless 1 <= order <= 3 (order 0 has no direction to decode).
void checkDecoderOrder(int order);

// The requested filter length, or the HRIR length + kDecoderFilterMargin for 0.
// InputError when shorter than the HRIRs.
std::size_t filterLength(const HrtfSet& hrtf, std::size_t requested);

// The frequency up to which order-N harmonics can follow a head's sound field: k r = N for
// a sphere of the usual head radius 8.75 cm (Algazi et al., "Approximating the head-related
// transfer function using simple geometric models of the head and torso", JASA 2002),
// N c / (2 pi r), about 625 Hz per order (Zotter & Frank, "Ambisonics", 2019, sec. 4.11).
double orderLimitFrequencyHz(int order);

// Per-ACN-channel gains at `frequency_hz` that apply max-rE weights (Daniel 2001) above
// orderLimitFrequencyHz and leave the channels untouched below it, crossing over with a
// raised cosine one octave wide on a log-frequency axis. Below the limit the order-N field
// is right around the head and tapering it would only shrink the ITD; above it, where the
// field breaks up, max-rE trades the spatial aliasing's side lobes for a wider main lobe
// (the two-band decoders of Gerzon and Daniel).
Eigen::VectorXd maxReTaper(int order, double frequency_hz);

// The powers of the ACN channels in a diffuse field of unit omnidirectional power: with
// SN3D the harmonics of degree l have mean square 1/(2l+1) over the sphere.
Eigen::VectorXd sn3dDiffuseChannelPowers(int order);

// Rows: the (order+1)^2 SN3D harmonics of each direction.
Eigen::MatrixXd harmonicMatrix(int order, const std::vector<Eigen::Vector3d>& directions);

// Spectra of pairs of responses, zero-padded to fft_size: one (pairs x 2) matrix per bin,
// column 0 the left ear. Of every HRIR of a set, or of every filter of a decoder.
std::vector<Eigen::MatrixXcd> pairSpectra(std::size_t count, const std::function<const Hrir&(std::size_t)>& pair,
                                          std::size_t fft_size);
std::vector<Eigen::MatrixXcd> hrtfSpectra(const HrtfSet& hrtf, std::size_t fft_size);
std::vector<Eigen::MatrixXcd> filterSpectra(const std::vector<Hrir>& filters, std::size_t fft_size);

// Decoder spectra (one (channels x 2) matrix per bin of an fft_size FFT) to FIRs of
// filter_length taps: inverse FFT, truncation, then a half-Hann fade over the last eighth
// so the truncation does not click (what the phase fit spread beyond filter_length is
// dropped; non-causal parts land at the end of the FFT frame, beyond the truncation).
std::vector<Hrir> filtersFromSpectra(const std::vector<Eigen::MatrixXcd>& spectra, std::size_t fft_size,
                                     std::size_t filter_length);

}  // namespace room_reverb::core::decoder_support
