#pragma once
// Physical constants and per-path propagation terms shared by the image sources, the ray
// tracer and the parametric tail.
#include <Eigen/Core>

#include "room_reverb/acoustics/air_absorption.h"

namespace room_reverb::core {

// Speed of sound in air [m/s] at a temperature, c = 331.3 sqrt(1 + T / 273.15).
double speedOfSoundMPerS(double temperature_c);

// A source's directivity from the cardioid family: pressure gain
// g(theta) = a + (1 - a) cos(theta) about `axis` (a = 1 omni, 0.5 cardioid, 0 figure-8),
// 1 on the axis.
struct SourceDirectivity {
  double omni_fraction = 1.0;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  double pressureGain(const Eigen::Vector3d& direction) const;  // direction: unit, leaving the source
  bool isOmni() const { return omni_fraction >= 1.0; }
};

// Everything the physics of a simulation needs besides the scene.
struct PropagationModel {
  AirConditions air;                 // air.enabled switches air absorption
  SourceDirectivity directivity;
  double speed_of_sound_m_s = 343.2;
  OctaveBandValues air_attenuation_per_m{};  // energy, from `air`

  static PropagationModel from(const AirConditions& air, const SourceDirectivity& directivity);
  // With the air absorbing at each band's given frequency (AcousticScene::bandCentresHz).
  static PropagationModel from(const AirConditions& air, const SourceDirectivity& directivity,
                               const OctaveBandValues& band_centres_hz);
};

}  // namespace room_reverb::core
