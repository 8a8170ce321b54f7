#include "room_reverb/acoustics/propagation.h"

#include <cmath>

namespace room_reverb::core {

double speedOfSoundMPerS(double temperature_c) { return 331.3 * std::sqrt(1.0 + temperature_c / 273.15); }

double SourceDirectivity::pressureGain(const Eigen::Vector3d& direction) const {
  if (isOmni()) return 1.0;
  return omni_fraction + (1.0 - omni_fraction) * axis.normalized().dot(direction);
}

PropagationModel PropagationModel::from(const AirConditions& air, const SourceDirectivity& directivity) {
  PropagationModel model;
  model.air = air;
  model.directivity = directivity;
  model.speed_of_sound_m_s = speedOfSoundMPerS(air.temperature_c);
  model.air_attenuation_per_m = airEnergyAttenuationPerM(air);
  return model;
}

PropagationModel PropagationModel::from(const AirConditions& air, const SourceDirectivity& directivity,
                                        const OctaveBandValues& band_centres_hz) {
  PropagationModel model = from(air, directivity);
  model.air_attenuation_per_m = airEnergyAttenuationPerM(air, band_centres_hz);
  return model;
}

}  // namespace room_reverb::core
