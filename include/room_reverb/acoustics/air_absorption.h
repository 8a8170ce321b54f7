#pragma once
// Atmospheric absorption of sound after ISO 9613-1:1993.
#include "room_reverb/acoustics/material.h"

namespace room_reverb::core {

struct AirConditions {
  bool enabled = true;
  double temperature_c = 20.0;
  double humidity_percent = 50.0;  // relative humidity
  double pressure_kpa = 101.325;
};

// Pure-tone attenuation coefficient alpha of ISO 9613-1 eq. (5), in dB per metre.
// Throws InputError for conditions outside the standard's validity (temperature
// -20..50 C, humidity 0..100 %, pressure 50..120 kPa).
double airAttenuationDbPerM(double frequency_hz, const AirConditions& air);

// Energy attenuation m per octave band (intensity falls as exp(-m d) over d metres),
// m = alpha / (10 log10 e), evaluated at each band's exact centre frequency. All zeros
// when air.enabled is false.
OctaveBandValues airEnergyAttenuationPerM(const AirConditions& air);
// The same at the given frequency of each band (a third-octave view's centres,
// AcousticScene::bandCentresHz).
OctaveBandValues airEnergyAttenuationPerM(const AirConditions& air, const OctaveBandValues& band_centres_hz);

// Reverberation time by Sabine, T = 0.161 V / (A + 4 m V), and by Eyring,
// T = 0.161 V / (-S ln(1 - mean_alpha) + 4 m V), in seconds. V in m^3, S and A in m^2,
// m in 1/m. Return +inf when nothing absorbs.
double sabineReverberationTimeS(double volume_m3, double absorption_area_m2, double air_m);
double eyringReverberationTimeS(double volume_m3, double surface_m2, double mean_absorption,
                                double air_m);

}  // namespace room_reverb::core
