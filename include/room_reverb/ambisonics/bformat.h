#pragma once
// First-order B-format conventions. Inside the project B-format is AmbiX: ACN channel
// order (W, Y, Z, X) with SN3D normalisation. Files recorded as FuMa (W, X, Y, Z with W
// at -3 dB) are converted at the edge; the caller states which one a file is.
#include <string>

#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

enum class AmbisonicFormat { kAmbiX, kFuMa };

// "ambix" or "fuma" (case-insensitive); anything else is an InputError.
AmbisonicFormat parseAmbisonicFormat(const std::string& name);
std::string toString(AmbisonicFormat format);

// ACN channel indices of first-order AmbiX.
constexpr int kAcnW = 0;
constexpr int kAcnY = 1;
constexpr int kAcnZ = 2;
constexpr int kAcnX = 3;

// Converts a 4-channel first-order buffer between conventions. FuMa W carries a 1/sqrt(2)
// weight relative to SN3D W; X, Y, Z have unit weight in both at first order.
AudioBuffer fumaToAmbix(const AudioBuffer& fuma);
AudioBuffer ambixToFuma(const AudioBuffer& ambix);
// Either conversion, or a copy when `from` equals AmbiX.
AudioBuffer toAmbix(const AudioBuffer& buffer, AmbisonicFormat from);

// The ambisonic order of an AmbiX buffer (1, 4, 9, 16 channels: 0-3); InputError naming
// `what` and the channel count otherwise.
int ambixOrder(const AudioBuffer& ambix, const std::string& what = "the room response");

// Diagnostic for a stated convention: in a diffuse field the energy of X+Y+Z over W is 1
// for SN3D and 2 for FuMa (whose W is 3 dB down). Returns that ratio over the late part
// (after `skip_s`) of a first-order RIR; both formats put W first, so the order of the
// other three does not matter here.
double diffuseDirectionalToOmniRatio(const AudioBuffer& buffer, double skip_s = 0.1);

// A warning text when the ratio contradicts the stated format (closer to the other
// convention's value by more than a factor 1.4), or an empty string.
std::string checkAmbisonicFormat(const AudioBuffer& buffer, AmbisonicFormat stated);

}  // namespace room_reverb::core
