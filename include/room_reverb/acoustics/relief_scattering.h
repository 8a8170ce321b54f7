#pragma once
// The scattering coefficient of a surface from its relief: what stands on it or is set
// into it (shelves and their contents, radiators, recessed doors, wall units the room
// model does not hold as objects), given as the heights of equal-area cells above
// (positive, into the room) or below the surface's plane.
//
// Kirchhoff's phase-screen approximation (Beckmann and Spizzichino, "The scattering of
// electromagnetic waves from rough surfaces", 1963, ch. 5): a plane wave at incidence
// angle theta reflects specularly with the mean of exp(i 2 k z cos theta) over the
// surface, so the specular share of the energy is that mean's squared magnitude. ISO
// 17497-1 defines the random-incidence scattering coefficient as one minus the specular
// share, averaged over a diffuse field's incidence (weight 2 mu on mu = cos theta):
//   s = 1 - sum_j sum_l w_j w_l g(2 k (z_j - z_l)),
//   g(a) = int_0^1 2 mu cos(a mu) dmu = 2 (sin a / a + (cos a - 1) / a^2).
// Nothing is fitted: the heights come from the capture, k from the band's centre. The
// approximation ignores shadowing and reflections within the relief; it holds where the
// relief's features are large against the wavelength, and below that it tends to the
// 2 k^2 var(z) of a slightly rough surface. A relief of one height everywhere scatters
// nothing (it is a plane moved), and the plane part of a surface keeps its coherent
// share: with a fraction p of the area plain, s stays below 1 - p^2.
#include <vector>

#include "room_reverb/acoustics/material.h"

namespace room_reverb::core {

// Per band: s at each band's centre (Hz). `heights_m`: one per equal-area cell of the
// surface, finite. InputError for an empty list, a non-finite height or speed of sound.
OctaveBandValues reliefScattering(const std::vector<double>& heights_m, double speed_of_sound_m_s,
                                  const OctaveBandValues& band_centres_hz = octaveCentresHz());

// Whether any band scatters: a relief of zeros is a plane face.
bool hasRelief(const OctaveBandValues& relief_scattering);

// The scattering of a surface whose material scatters s_m and whose relief scatters s_r:
// 1 - (1 - s_m)(1 - s_r), the specular shares multiplied (as ODEON combines its
// reflection-based scattering with the material's).
OctaveBandValues combinedScattering(const OctaveBandValues& material_scattering, const OctaveBandValues& relief_scattering);

}  // namespace room_reverb::core
