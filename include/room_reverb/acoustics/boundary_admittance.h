#pragma once
// What a wave solver's boundary needs from a material's random-incidence absorption: the
// specific (normalised by rho c) acoustic admittance beta of a locally reacting surface
// with that absorption. For real beta the absorption at incidence angle theta is
// 4 beta cos(theta) / (cos(theta) + beta)^2 (the plane-wave reflection factor of a
// locally reacting surface), and Paris's formula averages it over a diffuse field with
// weight sin(2 theta). A real admittance takes every value of the random-incidence
// absorption up to 0.9512 (at beta = 0.638); a larger one is given that maximum.
namespace room_reverb::core {

// Paris's average over incidence of a locally reacting surface with real specific
// admittance `beta` (>= 0).
double randomIncidenceAbsorption(double beta);

// The smallest beta whose random-incidence absorption is `alpha` (in [0, 1]; above the
// maximum of real admittances, the beta of that maximum). Monotone in alpha.
double admittanceForRandomIncidenceAbsorption(double alpha);

// The largest random-incidence absorption a real admittance reaches, and where.
constexpr double kMaxRealAdmittanceAbsorption = 0.9512;
constexpr double kAdmittanceOfMaxAbsorption = 0.6382;

}  // namespace room_reverb::core
