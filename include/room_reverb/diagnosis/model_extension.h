#pragma once
// The model under diagnosis and the extensions the diagnosis may add to it. Each extension
// is a few parameters of one cause in the catalogue (diagnosis.h); none changes the base
// model, so hypotheses can be tried, compared and combined freely.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/propagation.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/triangle_mesh.h"

namespace room_reverb::core {

// A second, slower decay added to the late response: the signature of a coupled volume
// (e.g. a stage house or a corridor behind an open door) seen from the main room.
struct CoupledDecay {
  double t60_s = 0.0;      // the coupled volume's decay time (all bands)
  double level_db = -30.0; // its energy envelope at the direct sound, re the direct sound's energy
                           // per band (the main decay's own level there is about 0 dB)
};

// The low band synthesised from the room's modes (acoustics/room_modes.h) instead of
// ray-traced: below the crossover the response is the sum of the box's modes, their
// damping from the model's absorption times `damping_scale`.
struct LowFrequencyModes {
  double damping_scale = 1.0;
  double crossover_hz = 0.0;  // where the modal band hands over to the rays (Schroeder)
};

struct ModelExtension {
  std::optional<AirConditions> air;
  // Absorption replaced per target: a room surface (floor, ceiling, wall_x_min, ...) or an
  // object's label for room models, a material name for meshes.
  std::map<std::string, OctaveBandValues> absorption;
  std::optional<double> global_scattering;
  std::optional<SourceDirectivity> directivity;
  double geometry_scale = 1.0;          // the room (and its objects) scaled about the origin
  std::vector<CuboidObject> reflectors; // objects the model lacked
  std::optional<CoupledDecay> coupled;
  std::optional<LowFrequencyModes> modes;
  // Physics the simulation has as switches, with nothing to fit: the scattering of the
  // surfaces' finite size, the low band from the wave solver, and third octaves end to end
  // (room_simulation.h).
  bool diffraction_scattering = false;
  bool wave_low_band = false;
  bool third_octave_bands = false;

  // `other`'s fields on top of these (maps merged, reflectors appended, scale multiplied).
  void add(const ModelExtension& other);
};

class RoomUnderTest {
 public:
  // A room model (DESIGN.md room.yaml) or a mesh with a material library.
  static RoomUnderTest fromRoomModel(RoomModel room, MaterialLibrary library);
  static RoomUnderTest fromMesh(TriangleMesh mesh, MaterialLibrary library, AirConditions air);

  bool isRoomModel() const { return room_.has_value(); }
  const AirConditions& air() const { return air_; }
  const MaterialLibrary& library() const { return library_; }

  // What a per-surface absorption fit may target: the room's used surfaces and objects, or
  // the mesh's materials; with each target's current absorption and area.
  std::vector<std::string> absorptionTargets() const;
  OctaveBandValues absorptionOf(const std::string& target) const;
  double areaOf(const std::string& target) const;

  AcousticScene scene(const ModelExtension& extension) const;
  AirConditions airWith(const ModelExtension& extension) const;
  // The room model with the extension written into it (fitted absorptions as inline
  // materials, reflectors as objects, scale, air); InputError for meshes.
  RoomModel extendedRoomModel(const ModelExtension& extension) const;

 private:
  std::optional<RoomModel> room_;
  TriangleMesh mesh_;
  MaterialLibrary library_;
  AirConditions air_;
};

}  // namespace room_reverb::core
