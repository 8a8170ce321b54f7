#include "planted_room.h"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <numeric>
#include <optional>
#include <random>
#include <sstream>

#include "room_reverb/acoustics/propagation.h"
#include "room_reverb/acoustics/room_simulation.h"

namespace room_reverb::test {
namespace {

using namespace room_reverb::core;

constexpr double kDuration = 0.8;

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

Eigen::Vector3d pointIn(std::mt19937& rng, const Eigen::Vector3d& size, double margin, double z_lo, double z_hi) {
  return {uniform(rng, margin, size.x() - margin), uniform(rng, margin, size.y() - margin), uniform(rng, z_lo, z_hi)};
}

RoomModel randomRoom(std::mt19937& rng, MaterialLibrary& library) {
  RoomModel room;
  room.size_m = {uniform(rng, 5.0, 7.0), uniform(rng, 3.8, 5.0), uniform(rng, 2.6, 3.2)};
  room.air = AirConditions{true, 20.0, 50.0, 101.325};
  for (const char* surface : kRoomSurfaceNames) {
    AcousticMaterial m;
    m.name = std::string("planted_") + surface;
    const double a = uniform(rng, 0.08, 0.25);
    for (std::size_t b = 0; b < m.absorption.size(); ++b) m.absorption[b] = std::min(0.9, a * (0.8 + 0.08 * b));
    m.scattering.fill(0.5);
    m.source = "diagnosis test";
    library.add(m);
    room.surfaces[surface] = SurfaceAssignment{m.name, 1.0};
  }
  return room;
}

// Whether the upright panel mirrors S to R (the specular point on its face, not its edge),
// and then the reflection's delay after the direct sound and its level re the direct
// sound (spreading and the panel's mean absorption).
struct PanelReflection {
  bool exists = false;
  double delay_s = 0.0, level_db = 0.0;
};

PanelReflection panelReflection(const CuboidObject& panel, const MeasurementPair& pair, double absorption,
                                double speed_of_sound_m_s) {
  const Eigen::Vector3d n(std::cos(panel.yaw_rad), std::sin(panel.yaw_rad), 0.0);
  const Eigen::Vector3d face = panel.center_m + 0.5 * panel.size_m.x() * (n.dot(pair.source_m - panel.center_m) > 0 ? n : -n);
  const double hs = n.dot(pair.source_m - face), hr = n.dot(pair.receiver_m - face);
  if (hs * hr <= 0.0) return {};  // on opposite sides of the panel
  const Eigen::Vector3d image = pair.source_m - 2.0 * hs * n;
  const Eigen::Vector3d point = image + (pair.receiver_m - image) * (std::abs(hs) / (std::abs(hs) + std::abs(hr)));
  const Eigen::Vector3d along(-n.y(), n.x(), 0.0);
  const Eigen::Vector3d local = point - face;
  if (std::abs(local.dot(along)) > 0.5 * panel.size_m.y() || std::abs(local.z()) > 0.5 * panel.size_m.z()) return {};
  const double direct = (pair.receiver_m - pair.source_m).norm(), reflected = (pair.receiver_m - image).norm();
  return {true, (reflected - direct) / speed_of_sound_m_s, 20.0 * std::log10(direct / reflected) + 10.0 * std::log10(1.0 - absorption)};
}

// A thin upright panel (wood) away from the pairs: the planted missing reflector. It is
// turned to mirror the source of a fit pair (even index) to its receiver, and kept only
// if a held-out pair (odd index) hears a reflection from it too, early (within 25 ms)
// and strong (at most 8 dB below the direct sound): a panel that no receiver hears has
// no effect a measurement could show. The rest (position, size, which pairs) is random.
CuboidObject randomPanel(std::mt19937& rng, const RoomModel& room, const std::vector<MeasurementPair>& pairs,
                         double absorption) {
  for (int attempt = 0; attempt < 5000; ++attempt) {
    CuboidObject panel;
    panel.label = "planted_panel";
    panel.material = "wood_panel";
    panel.size_m = {0.08, uniform(rng, 1.2, 1.6), uniform(rng, 1.0, 1.4)};
    const MeasurementPair& aim = pairs[2 * std::uniform_int_distribution<std::size_t>(0, pairs.size() / 2 - 1)(rng)];
    panel.center_m = pointIn(rng, room.size_m, 1.0, 0.9, 1.5);
    const Eigen::Vector3d to_s = (aim.source_m - panel.center_m).normalized(), to_r = (aim.receiver_m - panel.center_m).normalized();
    const Eigen::Vector3d bisector = to_s + to_r;
    panel.yaw_rad = std::atan2(bisector.y(), bisector.x());
    bool clear = true;
    for (const MeasurementPair& p : pairs) {
      clear = clear && (p.source_m - panel.center_m).norm() > 1.3 && (p.receiver_m - panel.center_m).norm() > 1.3;
    }
    if (!clear) continue;
    bool heard_by_fit = false, heard_held_out = false;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const PanelReflection r = panelReflection(panel, pairs[i], absorption, speedOfSoundMPerS(room.air.temperature_c));
      const bool heard = r.exists && r.delay_s < 0.025 && r.level_db > -8.0;
      (i % 2 == 0 ? heard_by_fit : heard_held_out) |= heard;
    }
    if (heard_by_fit && heard_held_out) return panel;
  }
  throw std::runtime_error("no room for a panel");
}

}  // namespace

std::uint32_t testSeed(std::uint32_t default_seed) {
  const char* env = std::getenv("ROOM_REVERB_TEST_SEED");
  const std::uint32_t seed = env ? static_cast<std::uint32_t>(std::strtoul(env, nullptr, 10)) : default_seed;
  std::cout << "[ seed     ] " << seed << " (rerun with ROOM_REVERB_TEST_SEED=" << seed << ")\n";
  return seed;
}

DiagnosisOptions testDiagnosisOptions() {
  DiagnosisOptions options;
  options.evaluation.simulation.rays.ray_count = 6000;
  options.evaluation.simulation.duration_s = kDuration;
  options.evaluation.simulation.image_source_order = 3;
  options.evaluation.simulation.rays.seed = 1;
  return options;
}

namespace {

// The room's materials made hard walls (absorption 0.03-0.06) between an absorbing floor
// and ceiling (0.45-0.6), the same in every band; their scattering set to `scattering`
// when given.
void absorbOnFloorAndCeiling(std::mt19937& rng, PlantedCase& c, std::optional<double> scattering) {
  for (const char* surface : kRoomSurfaceNames) {
    AcousticMaterial m = c.library.get(c.room.surfaces[surface].material);
    const bool horizontal = std::string(surface) == "floor" || std::string(surface) == "ceiling";
    const double a = horizontal ? uniform(rng, 0.45, 0.6) : uniform(rng, 0.03, 0.06);
    for (std::size_t b = 0; b < m.absorption.size(); ++b) m.absorption[b] = a;
    if (scattering) m.scattering.fill(*scattering);
    c.library.add(m);
  }
}

}  // namespace

PlantedCase plantedCase(const std::string& cause, std::uint32_t seed) {
  std::mt19937 rng(seed);
  PlantedCase c;
  c.seed = seed;
  c.cause = cause;
  c.library = MaterialLibrary::loadDefault();
  c.room = randomRoom(rng, c.library);
  // A surface's size scatters where it is a few wavelengths across: a small room's walls
  // at 125-500 Hz.
  const bool small = cause == "diffraction_scattering";
  if (small) c.room.size_m = {uniform(rng, 3.2, 3.8), uniform(rng, 2.4, 2.9), uniform(rng, 2.4, 2.7)};
  const double margin = small ? 0.5 : 0.8, separation = small ? 1.0 : 1.5;
  std::vector<MeasurementPair> pairs;
  const Eigen::Vector3d s1 = pointIn(rng, c.room.size_m, margin, 1.0, 1.6), s2 = pointIn(rng, c.room.size_m, margin, 1.0, 1.6);
  for (const Eigen::Vector3d& s : {s1, s2}) {
    for (int r = 0; r < 2; ++r) {
      MeasurementPair p;
      p.source_m = s;
      do p.receiver_m = pointIn(rng, c.room.size_m, margin, 1.1, 1.5);
      while ((p.receiver_m - s).norm() < separation);
      p.format = "ambix";
      p.label = "pair" + std::to_string(pairs.size() + 1);
      pairs.push_back(p);
    }
  }
  std::ostringstream d;
  ModelExtension& e = c.planted;
  if (cause == "air_absorption") {
    c.room.air.enabled = false;  // the naive model: no air
    e.air = AirConditions{true, 20.0, uniform(rng, 20.0, 45.0), 101.325};
    d << "air at 20 C, " << e.air->humidity_percent << " % (model: no air)";
  } else if (cause == "surface_absorption") {
    const std::string target = kRoomSurfaceNames[std::uniform_int_distribution<int>(0, 5)(rng)];
    OctaveBandValues alpha = c.library.get(c.room.surfaces[target].material).absorption;
    const double shift = uniform(rng, 0.2, 0.35);
    for (double& a : alpha) a = std::min(0.95, a + shift);
    e.absorption[target] = alpha;
    d << target << " absorption +" << shift;
  } else if (cause == "scattering") {
    // Scattering shows where absorption is uneven: with an absorbing floor and ceiling
    // and hard walls, specular rays that run between the walls outlive the rest, and the
    // late decay lengthens; diffuse ones mix into the absorbing surfaces. (With absorption
    // spread evenly, 0.2 against 0.5 changed EDT, C80 and D50 less than the ray noise.)
    absorbOnFloorAndCeiling(rng, c, std::nullopt);
    // Not lower: below about 0.1 the ray tracer's late energy is carried by a few rays
    // (see docs/diagnosis.md) and the "measurement" itself turns noisy.
    e.global_scattering = uniform(rng, 0.12, 0.2);
    d << "scattering " << *e.global_scattering << " (model 0.5), floor and ceiling absorbing";
  } else if (cause == "missing_reflector") {
    const OctaveBandValues& wood = c.library.get("wood_panel").absorption;
    e.reflectors.push_back(randomPanel(rng, c.room, pairs, std::accumulate(wood.begin(), wood.end(), 0.0) / wood.size()));
    d << "panel at " << e.reflectors[0].center_m.transpose() << " yaw " << e.reflectors[0].yaw_rad;
  } else if (cause == "geometry_scale") {
    const double k = rng() % 2 ? uniform(rng, 1.06, 1.12) : uniform(rng, 0.9, 0.94);
    e.geometry_scale = k;
    // Pairs must stay inside the smaller of the two rooms.
    for (MeasurementPair& p : pairs) {
      p.source_m *= std::min(1.0, k) * 0.97;
      p.receiver_m *= std::min(1.0, k) * 0.97;
    }
    d << "room scaled by " << k;
  } else if (cause == "coupled_volume") {
    e.coupled = CoupledDecay{uniform(rng, 1.6, 2.4), uniform(rng, 0.0, 6.0)};
    d << "coupled decay T60 " << e.coupled->t60_s << " s at " << e.coupled->level_db << " dB";
  } else if (cause == "source_directivity") {
    SourceDirectivity dir;
    dir.omni_fraction = uniform(rng, 0.3, 0.55);
    const double az = uniform(rng, -M_PI, M_PI);
    dir.axis = {std::cos(az), std::sin(az), 0.0};
    e.directivity = dir;
    d << "source pattern a = " << dir.omni_fraction << " towards azimuth " << az * 180 / M_PI << " deg";
  } else if (cause == "low_frequency_modes") {
    // The truth's low band is modal, with the wall damping off the tables by a factor.
    const double scale = rng() % 2 ? uniform(rng, 1.4, 2.0) : uniform(rng, 0.5, 0.7);
    const RoomUnderTest room = RoomUnderTest::fromRoomModel(c.room, c.library);
    e.modes = LowFrequencyModes{scale, modalCrossoverHz(room.scene({}), c.room.air)};
    d << "modal low band below " << e.modes->crossover_hz << " Hz, damping x " << scale;
  } else if (cause == "diffraction_scattering") {
    // Smooth surfaces, absorption on the floor and ceiling: the walls' finite size is what
    // scatters the low bands into the absorbing surfaces.
    absorbOnFloorAndCeiling(rng, c, 0.1);
    e.diffraction_scattering = true;
    d << "diffraction scattering (model: materials' 0.1 alone), floor and ceiling absorbing";
  } else if (!cause.empty()) {
    throw std::runtime_error("unknown planted cause " + cause);
  } else {
    d << "nothing planted";
  }
  c.description = d.str();

  // The measurement: the room with the planted extension, simulated in B-format.
  const RoomUnderTest truth = RoomUnderTest::fromRoomModel(c.room, c.library);
  const AcousticScene scene = truth.scene(e);
  SimulationSettings s;
  s.duration_s = kDuration;
  s.ambisonic_order = 1;
  s.air = truth.airWith(e);
  if (e.directivity) s.directivity = *e.directivity;
  s.diffraction_scattering = e.diffraction_scattering;
  if (e.wave_low_band) s.low_band = LowBandMethod::kWave;
  if (e.third_octave_bands) s.bands = BandResolution::kThirdOctave;
  s.rays.ray_count = 30000;
  c.evidence.positions = pairs;
  const ModalRoom modal_room = modalRoomFor(scene, s.air);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    s.rays.seed = 5000 + seed % 1000 + static_cast<std::uint32_t>(i);
    SimulationResult r = simulateRoom(scene, pairs[i].source_m, pairs[i].receiver_m, s);
    // The effects the extension adds to a response, by the same code (a coupled decay on
    // the omni channel only: the scored evidence is all omni, and a diffuse tail carries
    // no direction worth modelling; the modes in all four channels).
    applyResponseExtensions(r.impulse_response, e, &modal_room, pairs[i], r.paths.front().delay_s, s.rays.seed + 77);
    c.evidence.rirs.push_back(analysePair(pairs[i], r.impulse_response));
  }
  std::cout << "[ planted  ] " << c.description << "\n";
  return c;
}

}  // namespace room_reverb::test
