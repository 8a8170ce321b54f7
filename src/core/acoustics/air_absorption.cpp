#include "room_reverb/acoustics/air_absorption.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

// Reference values of ISO 9613-1: reference pressure (one standard atmosphere), reference
// temperature (20 C) and the triple-point isotherm temperature of water.
constexpr double kReferencePressureKpa = 101.325;
constexpr double kReferenceTemperatureK = 293.15;
constexpr double kTriplePointK = 273.16;
constexpr double kCelsiusToKelvin = 273.15;

std::string formatNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

void checkRange(double value, double low, double high, const char* what, const char* unit) {
  if (std::isfinite(value) && value >= low && value <= high) return;
  throw InputError(std::string("air ") + what + " " + formatNumber(value) + " " + unit +
                   " is outside the range ISO 9613-1 covers here (" + formatNumber(low) + " .. " +
                   formatNumber(high) + " " + unit + ")");
}

void checkConditions(const AirConditions& air) {
  checkRange(air.temperature_c, -20.0, 50.0, "temperature", "C");
  checkRange(air.humidity_percent, 0.0, 100.0, "relative humidity", "%");
  checkRange(air.pressure_kpa, 50.0, 120.0, "pressure", "kPa");
}

// Molar concentration of water vapour h in percent, from relative humidity (annex B):
// the saturation vapour pressure relative to the reference pressure is 10^C with
// C = -6.8346 (T01 / T)^1.261 + 4.6151, and h = h_r (p_sat / p_r) / (p_a / p_r).
double molarWaterVapourPercent(double temperature_k, double humidity_percent, double pressure_kpa) {
  const double exponent = -6.8346 * std::pow(kTriplePointK / temperature_k, 1.261) + 4.6151;
  const double saturation_ratio = std::pow(10.0, exponent);  // p_sat / p_r
  return humidity_percent * saturation_ratio / (pressure_kpa / kReferencePressureKpa);
}

}  // namespace

double airAttenuationDbPerM(double frequency_hz, const AirConditions& air) {
  // Disabled air means no propagation loss, like airEnergyAttenuationPerM.
  if (!air.enabled) return 0.0;
  if (!std::isfinite(frequency_hz) || frequency_hz <= 0.0) {
    throw InputError("air absorption needs a positive frequency, got " +
                     formatNumber(frequency_hz) + " Hz");
  }
  checkConditions(air);

  const double temperature_k = air.temperature_c + kCelsiusToKelvin;
  const double pressure_ratio = air.pressure_kpa / kReferencePressureKpa;   // p_a / p_r
  const double temperature_ratio = temperature_k / kReferenceTemperatureK;  // T / T0
  const double h = molarWaterVapourPercent(temperature_k, air.humidity_percent, air.pressure_kpa);

  // Relaxation frequencies of oxygen, eq. (3), and nitrogen, eq. (4), in Hz. Water vapour
  // speeds up both relaxations, which is why humid air absorbs differently from dry air.
  const double relax_oxygen_hz = pressure_ratio * (24.0 + 4.04e4 * h * (0.02 + h) / (0.391 + h));
  const double relax_nitrogen_hz =
      pressure_ratio * std::pow(temperature_ratio, -0.5) *
      (9.0 + 280.0 * h * std::exp(-4.170 * (std::pow(temperature_ratio, -1.0 / 3.0) - 1.0)));

  // Eq. (5): a classical term (viscosity and heat conduction, growing with f^2) plus one
  // relaxation term per gas, each peaking around its relaxation frequency.
  const double f2 = frequency_hz * frequency_hz;
  const double classical = 1.84e-11 / pressure_ratio * std::sqrt(temperature_ratio);
  const double oxygen =
      0.01275 * std::exp(-2239.1 / temperature_k) / (relax_oxygen_hz + f2 / relax_oxygen_hz);
  const double nitrogen =
      0.1068 * std::exp(-3352.0 / temperature_k) / (relax_nitrogen_hz + f2 / relax_nitrogen_hz);
  return 8.686 * f2 * (classical + std::pow(temperature_ratio, -2.5) * (oxygen + nitrogen));
}

OctaveBandValues airEnergyAttenuationPerM(const AirConditions& air) {
  return airEnergyAttenuationPerM(air, octaveCentresHz());
}

OctaveBandValues airEnergyAttenuationPerM(const AirConditions& air, const OctaveBandValues& band_centres_hz) {
  OctaveBandValues m{};
  if (!air.enabled) return m;
  // alpha is a level decay in dB/m; intensity exp(-m d) falls by 10 log10(e) m dB per metre.
  const double db_per_neper_energy = 10.0 * std::log10(std::exp(1.0));
  for (std::size_t i = 0; i < m.size(); ++i) m[i] = airAttenuationDbPerM(band_centres_hz[i], air) / db_per_neper_energy;
  return m;
}

namespace {

void checkRoomInputs(double volume_m3, double air_m) {
  if (!std::isfinite(volume_m3) || volume_m3 <= 0.0) {
    throw InputError("reverberation time needs a positive room volume, got " +
                     formatNumber(volume_m3) + " m^3");
  }
  if (!std::isfinite(air_m) || air_m < 0.0) {
    throw InputError("reverberation time needs a non-negative air attenuation, got " +
                     formatNumber(air_m) + " 1/m");
  }
}

// 0.161 s/m is 24 ln(10) / c at c = 343 m/s, the constant of the Sabine formula.
constexpr double kSabineConstant = 0.161;

double reverberationTime(double volume_m3, double total_absorption_m2) {
  if (total_absorption_m2 <= 0.0) return std::numeric_limits<double>::infinity();
  return kSabineConstant * volume_m3 / total_absorption_m2;
}

}  // namespace

double sabineReverberationTimeS(double volume_m3, double absorption_area_m2, double air_m) {
  checkRoomInputs(volume_m3, air_m);
  if (!std::isfinite(absorption_area_m2) || absorption_area_m2 < 0.0) {
    throw InputError("Sabine reverberation time needs a non-negative absorption area, got " +
                     formatNumber(absorption_area_m2) + " m^2");
  }
  return reverberationTime(volume_m3, absorption_area_m2 + 4.0 * air_m * volume_m3);
}

double eyringReverberationTimeS(double volume_m3, double surface_m2, double mean_absorption,
                                double air_m) {
  checkRoomInputs(volume_m3, air_m);
  if (!std::isfinite(surface_m2) || surface_m2 < 0.0) {
    throw InputError("Eyring reverberation time needs a non-negative surface area, got " +
                     formatNumber(surface_m2) + " m^2");
  }
  if (!std::isfinite(mean_absorption) || mean_absorption < 0.0 || mean_absorption > 1.0) {
    throw InputError("Eyring reverberation time needs a mean absorption in [0, 1], got " +
                     formatNumber(mean_absorption));
  }
  // A fully absorbing room (mean alpha = 1) has no reverberation: -ln(0) is infinite.
  if (mean_absorption >= 1.0 && surface_m2 > 0.0) return 0.0;
  // log1p keeps small absorptions accurate, where Eyring must approach Sabine.
  const double surface_term = surface_m2 > 0.0 ? -surface_m2 * std::log1p(-mean_absorption) : 0.0;
  return reverberationTime(volume_m3, surface_term + 4.0 * air_m * volume_m3);
}

}  // namespace room_reverb::core
