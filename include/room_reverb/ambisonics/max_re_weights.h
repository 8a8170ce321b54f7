#pragma once
// max-rE order weights ("in-phase"-like tapering that maximises the energy vector).
//
// Weighting the harmonics of degree l by a_l = P_l(cos(theta_E)), with theta_E =
// 137.9 deg / (N + 1.51), maximises the length |rE| of Gerzon's energy vector of an
// order-N panning function, which narrows the spread of its energy and lowers its side
// lobes (Daniel 2001, thesis, ch. 3; the closed-form approximation is Zotter & Frank,
// "Ambisonics", Springer 2019, sec. 3.10.3 / 4.6). a_0 = 1, so the omnidirectional part,
// the pressure at the centre, is left as it is.
#include <vector>

namespace room_reverb::core {

// a_0 .. a_N for order N (0..3). Order 0 gives {1}.
std::vector<double> maxReDegreeWeights(int order);

// The same weights repeated per ACN channel: (N+1)^2 entries, channel l^2 + l + m gets a_l.
std::vector<double> maxReChannelWeights(int order);

}  // namespace room_reverb::core
