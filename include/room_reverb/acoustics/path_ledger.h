#pragma once
// The ray tracer's paths, kept so that a model that differs only in its absorption, its
// air or its source directivity is answered without tracing again.
//
// A path's geometry does not depend on absorption: the rays leave in the same directions,
// meet the same walls and choose specular or diffuse with the same numbers (the tracer's
// random numbers are keyed to the branch, ray_tracer.cpp), as long as the scattering is
// the same. What a path delivers is a product over the walls it met, (1 - alpha) per
// reflection, times the air's exp(-m d) and the source's gain in its launch direction. The
// ledger records each branch's walls, its arrivals at the receiver (distance, direction,
// geometric factor) and the factors of the Russian roulette it survived; replaying it with
// other reflectances, air and directivity gives the histogram those would have given, in
// expectation: the roulette's decisions were taken on the traced energies, and a survivor
// keeps the weight it earned there, which leaves the estimate unbiased (the roulette is a
// random weighting of a path that the new model would have followed as well).
//
// What reweighting costs is variance: where the new model lets paths last that the traced
// one faded (much less absorption on a surface they keep meeting), a few roulette
// survivors carry the new model's late energy. The replay measures this as the effective
// number of rays in each band's decay range and refuses when it falls too far
// (replayLedger: `why_not`), so the caller traces instead.
#include <cstdint>
#include <string>
#include <vector>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/energy_histogram.h"
#include "room_reverb/acoustics/propagation.h"

namespace room_reverb::core {

// One step of a branch, in the order the tracer took them (32 bytes; the distance in
// double so that a replay puts every arrival in the bin the tracer put it in).
struct LedgerEvent {
  enum Kind : std::uint32_t {
    kLaunch = 0,    // a new ray: direction = launch direction
    kReflect = 1,   // a wall (code's index = triangle); factor > 0: diffuse rain at distance_m from direction
    kSphere = 2,    // crossed the detection sphere: energy x factor at distance_m from direction
    kRoulette = 3,  // survived the roulette: energy x factor
    kSplit = 4,     // bands split (index = the diffuse bands' mask; the specular part is queued)
    kEnd = 5,       // the branch ended (left, time limit, roulette)
    kPark = 6,      // the branch waits for the next slice of time
    kSlice = 7,     // the chunk's parked branches resume, in the order they were parked
    kResume = 8,    // the next parked branch resumes
  };
  std::uint32_t code = 0;  // kind << 28 | index
  float factor = 0.0f;
  double distance_m = 0.0;
  float direction[3] = {0.0f, 0.0f, 0.0f};

  Kind kind() const { return static_cast<Kind>(code >> 28); }
  std::uint32_t index() const { return code & 0x0fffffffu; }
  static std::uint32_t makeCode(Kind kind, std::uint32_t index) { return (static_cast<std::uint32_t>(kind) << 28) | index; }
};

struct PathLedger {
  // Per chunk of `rays_per_chunk` rays, in the tracer's order; chunk c was traced by
  // thread c mod `threads`, whose histograms add in thread order.
  std::vector<std::vector<LedgerEvent>> chunks;
  std::size_t rays_per_chunk = 0;
  int threads = 1;
  Eigen::Vector3d source = Eigen::Vector3d::Zero();
  Eigen::Vector3d listener = Eigen::Vector3d::Zero();
  std::uint32_t seed = 0;
  std::size_t ray_count = 0;
  double ray_energy = 0.0;  // J per ray before the directivity
  double bin_s = 0.001;
  std::size_t bins = 0;
  double speed_of_sound_m_s = 343.2;
  int image_source_order = 3;               // specular paths up to it were not counted
  std::uint64_t mesh_fingerprint = 0;       // meshFingerprint of the traced scene
  SourceDirectivity directivity;            // of the traced model
  std::vector<OctaveBandValues> reflectance;  // per triangle, of the traced scene
  std::vector<OctaveBandValues> scattering;   // per triangle, of the traced scene
  // Per band, the travel (m) over which the traced decay curve (Schroeder's backward
  // integral of its histogram) falls from 5 to 35 dB down (decayRange): where the traced
  // walls' effective rays are counted.
  OctaveBandValues decay_from_m{};
  OctaveBandValues decay_to_m{};
  std::size_t bytes() const;
};

// Per band, the travel (m) over which the decay curve of `histogram` falls from 5 to 35 dB
// down (to its end where it does not).
void decayRange(const EnergyHistogram& histogram, double speed_of_sound_m_s, OctaveBandValues& from_m,
                OctaveBandValues& to_m);

struct LedgerReplayOptions {
  // The replay is refused when, in any band, the effective number of rays, (sum w)^2 /
  // sum w^2 over the rays' energies in the replayed decay's range (decayRange), falls below
  // this share of what the traced walls give in the traced decay's range (with the new
  // source and air: a directive source traced afresh weights its rays the same way).
  double min_effective_share = 0.5;
  int threads = 0;  // 0: the ledger's
};

struct LedgerReplay {
  bool replayed = false;
  std::string why_not;         // when not replayed
  EnergyHistogram histogram;   // when replayed
  OctaveBandValues effective_share{};  // per band: effective rays, replayed over traced
};

// A hash of a mesh's vertices and triangles: the same only for the same geometry.
std::uint64_t meshFingerprint(const TriangleMesh& mesh);

// The traced histogram of `scene` (same mesh and scattering as the ledger's, other
// absorption) under `model` (same speed of sound, any air and directivity). Refuses (why_not)
// a scene with other triangles or scattering, another speed of sound, a surface the traced
// scene made fully absorbing that now reflects, or too few effective rays.
LedgerReplay replayLedger(const PathLedger& ledger, const AcousticScene& scene, const PropagationModel& model,
                          const LedgerReplayOptions& options = {});

}  // namespace room_reverb::core
