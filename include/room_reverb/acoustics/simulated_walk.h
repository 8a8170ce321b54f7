#pragma once
// The simulated route heard by a listener who walks (docs/six_dof.md): the image-source
// part (the direct sound and the specular reflections up to the settings' order, from the
// room model's box and objects) computed again at every listener position, and the late
// part of one simulation at a reference position kept, as a diffuse field changes little
// across a room. Both parts are the simulator's own: at the reference position earlyAt()
// plus late() is simulateRoom()'s impulse response, sample for sample, in octaves or in
// third octaves (SimulationSettings::bands).
#include <Eigen/Core>
#include <vector>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/audio/audio_buffer.h"

namespace room_reverb::core {

class SimulatedWalk {
 public:
  // Simulates the room at `reference_listener_m` (simulateRoom's InputErrors for bad
  // positions or settings).
  SimulatedWalk(AcousticScene scene, const Eigen::Vector3d& source_m, const Eigen::Vector3d& reference_listener_m,
                const SimulationSettings& settings);
  // With the late part simulated elsewhere (the room_simulator node's late_part) for these
  // settings at `reference_listener_m`: AmbiX of the settings' ambisonic order at 48 kHz
  // (InputError otherwise, or for positions the scene refuses).
  SimulatedWalk(AcousticScene scene, const Eigen::Vector3d& source_m, const Eigen::Vector3d& reference_listener_m,
                const SimulationSettings& settings, AudioBuffer late);

  // The image-source part at `listener_m`, at the settings' ambisonic order and 48 kHz,
  // to the end of its last path's band-shaping FIR (21 ms after it). InputError for a listener outside the
  // room, inside an object or within 5 cm of the source.
  AudioBuffer earlyAt(const Eigen::Vector3d& listener_m) const;
  // The image sources at `listener_m` (the paths earlyAt synthesises); the same checks.
  std::vector<SpecularPath> pathsAt(const Eigen::Vector3d& listener_m) const;
  // The whole response heard at `listener_m`: earlyAt() over late(), the settings'
  // duration long (at the reference position, simulateRoom()'s response).
  AudioBuffer responseAt(const Eigen::Vector3d& listener_m) const;
  // The same from an early part earlyAt() has already given.
  AudioBuffer responseWith(const AudioBuffer& early) const;
  // The checks earlyAt and pathsAt make of a listener position, without computing anything:
  // InputError for a position that is not finite, outside the room, inside an object or
  // within 5 cm of the source.
  void requireListener(const Eigen::Vector3d& listener_m) const;
  // The late part at the reference position, the settings' duration long.
  const AudioBuffer& late() const { return late_; }

  const Eigen::Vector3d& sourcePosition() const { return source_m_; }
  const Eigen::Vector3d& referenceListener() const { return reference_m_; }
  const SimulationSettings& settings() const { return settings_; }
  const AcousticScene& scene() const { return scene_; }

 private:
  AcousticScene scene_;
  Eigen::Vector3d source_m_, reference_m_;
  SimulationSettings settings_;
  SynthesisOptions synthesis_;
  AudioBuffer late_;
  // In third octaves, the scene's three views (AcousticScene::thirdOctaveBands) whose image
  // sources make each early part; empty in octaves.
  std::vector<AcousticScene> third_views_;
  void makeThirdViews();
};

}  // namespace room_reverb::core
