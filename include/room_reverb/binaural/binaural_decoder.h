#pragma once
// Ambisonic (AmbiX: ACN, SN3D) to binaural decoders of orders 1-3.
//
// A decoder is a filter set: for every ACN channel a left and a right FIR, so that the
// binaural signal is sum_ch conv(ambisonic_ch, filter_ch). Two ways to make one:
//
// - Virtual loudspeakers: a mode-matching decoder (Moore-Penrose pseudo-inverse of the
//   layout's harmonic matrix, Zotter & Frank, "Ambisonics", Springer 2019, sec. 4.9.3)
//   onto a loudspeaker layout, each loudspeaker rendered with its HRIR. Simple and
//   classic, but its high frequencies are order-truncated HRTFs sampled at the
//   loudspeakers: the interaural cues of a plane wave smear and the sound gets darker.
// - SH-domain fits of the HRTF set itself: complex least squares (LS) of the HRTFs onto
//   the order-N harmonics, and magnitude least squares (MagLS; Schoerkhuber, Zaunschirm &
//   Hoeldrich, "Binaural rendering of Ambisonic signals via magnitude least squares",
//   DAGA 2018), which above a cutoff fits only the magnitudes and lets the phase follow
//   the previous frequency's solution. Order-N harmonics cannot follow the HRTF phase
//   above about kr = N (r the head radius), but the ear only uses interaural phase below
//   about 1.5 kHz; giving up the phase there buys correct magnitudes, hence correct ILDs
//   and timbre. Optionally followed by the diffuse-field covariance constraint (Zaunschirm,
//   Schoerkhuber & Hoeldrich, JASA 143(6), 2018), which restores the HRTF set's
//   diffuse-field level and interaural coherence that order truncation loses.
//
// docs/binaural_decoders.md compares them on the KU100 set. MagLS with the covariance
// constraint is the default: the smallest ILD errors at every order (0.9 dB mean at order
// 3, against 2.0-2.2 dB for the others), the same ITD as least squares at order 3, and
// the HRTF set's diffuse-field level and coherence, which matter for reverberation. (At
// orders 1 and 2, whose cutoffs lie below 1.5 kHz, its ITD errs more than least
// squares': 149 against 135 us and 66 against 45 us.)
//
// Timing: the SH fits take the HRTF set's bulk delay out before fitting and put it back
// after, so a decoded plane wave arrives when the direct HRIR would (no added latency);
// what the magnitude fit spreads before t = 0 (under 1 % of the filter energy for the
// KU100 set) is cut.
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/binaural/hrtf_set.h"

namespace room_reverb::core {

enum class DecoderMethod { kVirtualLoudspeakers, kLeastSquares, kMagLs };

// "virtual_loudspeakers", "least_squares" or "magls". InputError otherwise.
DecoderMethod parseDecoderMethod(const std::string& name);
std::string toString(DecoderMethod method);

struct BinauralDecoder {
  int order = 0;
  double sample_rate_hz = kInternalSampleRateHz;
  std::vector<Hrir> filters;  // one left/right FIR pair per ACN channel, for SN3D input
  std::string method;         // how it was made, for logs and reports
};

// Filter length when an options struct leaves it at 0: the HRIR length plus this margin
// (256 taps, 5.3 ms at 48 kHz, for the 128-tap KU100 set). The margin holds the spread
// that MagLS's frequency-by-frequency phase adds to the HRIRs' own length.
constexpr std::size_t kDecoderFilterMargin = 128;

struct VirtualLoudspeakerOptions {
  // Taper the orders with max-rE weights (Daniel 2001) above the frequency where order N
  // stops describing the field around the head (k r = N), not below, where they would
  // only shrink the ITD: narrower, smoother panning where the field breaks up anyway.
  bool max_re_weights = true;
  bool interpolate_hrirs = true;  // HrtfSet::interpolated(); false: the nearest measured HRIR
  std::size_t filter_length = 0;  // 0: HRIR length + kDecoderFilterMargin
};

struct ShDecoderOptions {
  // max-rE weights above k r = N as for virtual loudspeakers. Off: on the KU100 set they
  // raise the mean ILD error of MagLS at order 3 from 0.85 to 1.0 dB.
  bool max_re_weights = false;
  bool diffuse_field_covariance = true;  // Zaunschirm et al. 2018 constraint, per frequency
  std::size_t filter_length = 0;         // 0: HRIR length + kDecoderFilterMargin
};

struct MagLsOptions : ShDecoderOptions {
  // Above it only magnitudes are fitted. 0: the frequency where k r = N for a head of
  // radius 8.75 cm, N c / (2 pi r), about 625 Hz per order (624, 1248, 1872 Hz): below it
  // the order-N fit of the complex HRTF is accurate (Zotter & Frank 2019, sec. 4.11). A
  // fixed 2 kHz, as in the eMagLS reference code, would ask orders 1 and 2 to fit phases
  // they cannot follow; a lower cutoff trades ITD for ILD (at order 3, 1.5 kHz: ILD error
  // 0.80 instead of 0.85 dB, ITD error 15 instead of 12 us on the KU100 set).
  double cutoff_hz = 0.0;
};

// Throws InputError for an order outside 1..3, an empty layout, fewer loudspeakers than
// (order+1)^2, or a filter length shorter than the HRIRs.
BinauralDecoder makeVirtualLoudspeakerDecoder(const HrtfSet& hrtf, int order,
                                              const std::vector<Eigen::Vector3d>& layout,
                                              const VirtualLoudspeakerOptions& options = {});
// Throws InputError for an order outside 1..3, an HRTF set with fewer directions than
// (order+1)^2 or a filter length shorter than the HRIRs.
BinauralDecoder makeLeastSquaresDecoder(const HrtfSet& hrtf, int order, const ShDecoderOptions& options = {});
BinauralDecoder makeMagLsDecoder(const HrtfSet& hrtf, int order, const MagLsOptions& options = {});

// The project's choice for a method, with that method's default options (virtual
// loudspeakers on kDefaultLoudspeakerLayout).
BinauralDecoder makeBinauralDecoder(const HrtfSet& hrtf, int order, DecoderMethod method = DecoderMethod::kMagLs);

// sum_ch conv(ambix_ch, filter_ch) for each ear: two channels of length frames +
// filter length - 1 at the decoder's rate. InputError unless the buffer is valid, has
// (order+1)^2 channels and the decoder's sample rate.
AudioBuffer decodeToBinaural(const AudioBuffer& ambix, const BinauralDecoder& decoder);

// The binaural response of the decoder to a unit plane wave (impulse) from `direction`:
// sum_ch Y_ch(direction) filter_ch, what decodeToBinaural gives for that input.
Hrir decodedPlaneWaveResponse(const BinauralDecoder& decoder, const Eigen::Vector3d& direction);

}  // namespace room_reverb::core
