#include "room_reverb/acoustics/path_ledger.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <thread>

#include "room_reverb/acoustics/air_loss_table.h"
#include "room_reverb/common/hash_mix.h"

namespace room_reverb::core {
namespace {

// A branch being replayed: its energy per band under the new model and under the traced
// one, and the ray it belongs to.
struct ReplayBranch {
  OctaveBandValues energy{};
  OctaveBandValues traced{};
  std::size_t ray = 0;
};

// Per ray and band, the energy it delivered inside the decay range: [ray][band][new, traced
// walls with the new source and air].
using RayShares = std::vector<std::array<std::array<double, 2>, kOctaveBandCount>>;

struct ChunkReplay {
  const PathLedger& ledger;
  const std::vector<OctaveBandValues>& reflectance;  // the new model's, per triangle
  const PropagationModel& model;
  const AirLossTable& air;  // of the new model
  // With `shares`: count the rays' energies, replayed in the replay's decay range
  // (from_m, to_m) and with the traced walls in the traced decay's.
  RayShares* shares = nullptr;
  OctaveBandValues from_m{}, to_m{};
  double counted_from_m = 0.0, counted_to_m = 0.0;  // the union of both ranges over the bands

  void deposit(EnergyHistogram& histogram, const ReplayBranch& b, const OctaveBandValues* scattering,
               const LedgerEvent& e) const {
    const double d = e.distance_m;
    if (shares && (d < counted_from_m || d >= counted_to_m)) return;
    const Eigen::Vector3d direction(e.direction[0], e.direction[1], e.direction[2]);
    OctaveBandValues energy, weight;
    air.loss(d, e.factor, weight);  // as the tracer computes it
    for (int k = 0; k < kOctaveBandCount; ++k) energy[k] = b.energy[k] * (scattering ? (*scattering)[k] : 1.0);
    // The counting pass only adds up each ray's energies: the histogram is the first pass's.
    if (!shares) {
      histogram.addBands(d / ledger.speed_of_sound_m_s, energy, weight, direction);
      return;
    }
    auto& mine = (*shares)[b.ray];
    for (int k = 0; k < kOctaveBandCount; ++k) {
      const double s = scattering ? (*scattering)[k] : 1.0;
      if (d >= from_m[k] && d < to_m[k]) mine[k][0] += energy[k] * weight[k];
      if (d >= ledger.decay_from_m[k] && d < ledger.decay_to_m[k]) mine[k][1] += b.traced[k] * s * weight[k];
    }
  }

  void run(std::size_t chunk, EnergyHistogram& histogram) const {
    std::vector<ReplayBranch> pending, parked_next, parked;
    std::size_t resume_at = 0;
    std::size_t next_ray = chunk * ledger.rays_per_chunk;
    ReplayBranch branch;
    const auto endBranch = [&]() {
      if (pending.empty()) return;
      branch = pending.back();
      pending.pop_back();
    };
    for (const LedgerEvent& e : ledger.chunks[chunk]) {
      switch (e.kind()) {
        case LedgerEvent::kLaunch: {
          const Eigen::Vector3d direction(e.direction[0], e.direction[1], e.direction[2]);
          const double gain = model.directivity.pressureGain(direction);
          branch.energy.fill(ledger.ray_energy * gain * gain);
          // The reference of the effective count: the traced walls with the new source. A
          // directive source traced afresh weights its rays the same way, so only what
          // the walls' reweighting costs is held against the replay.
          branch.traced.fill(ledger.ray_energy * gain * gain);
          branch.ray = next_ray++;
          break;
        }
        case LedgerEvent::kReflect: {
          const std::size_t t = e.index();
          for (int k = 0; k < kOctaveBandCount; ++k) {
            branch.energy[k] *= reflectance[t][k];
            branch.traced[k] *= ledger.reflectance[t][k];
          }
          if (e.factor > 0.0f) deposit(histogram, branch, &ledger.scattering[t], e);
          break;
        }
        case LedgerEvent::kSphere: deposit(histogram, branch, nullptr, e); break;
        case LedgerEvent::kRoulette:
          for (int k = 0; k < kOctaveBandCount; ++k) {
            branch.energy[k] *= e.factor;
            branch.traced[k] *= e.factor;
          }
          break;
        case LedgerEvent::kSplit: {
          ReplayBranch specular = branch;
          const std::uint32_t diffuse = e.index();
          for (int k = 0; k < kOctaveBandCount; ++k) {
            if (diffuse >> k & 1u) {
              specular.energy[k] = specular.traced[k] = 0.0;
            } else {
              branch.energy[k] = branch.traced[k] = 0.0;
            }
          }
          pending.push_back(specular);
          break;
        }
        case LedgerEvent::kEnd: endBranch(); break;
        case LedgerEvent::kPark:
          parked_next.push_back(branch);
          endBranch();
          break;
        case LedgerEvent::kSlice:
          parked.swap(parked_next);
          parked_next.clear();
          resume_at = 0;
          break;
        case LedgerEvent::kResume: branch = parked[resume_at++]; break;
      }
    }
  }
};

// The chunks replayed on the ledger's threads (chunk c on thread c mod T), the threads'
// histograms added in thread order as the tracer adds them.
EnergyHistogram replayAll(const PathLedger& ledger, const ChunkReplay& replay, int threads) {
  std::vector<EnergyHistogram> parts(static_cast<std::size_t>(threads), EnergyHistogram(ledger.bin_s, ledger.bins));
  const auto work = [&](int t) {
    for (std::size_t c = static_cast<std::size_t>(t); c < ledger.chunks.size(); c += static_cast<std::size_t>(threads)) {
      replay.run(c, parts[static_cast<std::size_t>(t)]);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& thread : pool) thread.join();
  EnergyHistogram total(ledger.bin_s, ledger.bins);
  for (const EnergyHistogram& part : parts) total.merge(part);
  return total;
}

}  // namespace

void decayRange(const EnergyHistogram& histogram, double speed_of_sound_m_s, OctaveBandValues& from_m,
                OctaveBandValues& to_m) {
  for (int k = 0; k < kOctaveBandCount; ++k) {
    std::vector<double> tail(histogram.bins() + 1, 0.0);
    for (std::size_t n = histogram.bins(); n-- > 0;) tail[n] = tail[n + 1] + histogram.energy(n, k);
    from_m[k] = to_m[k] = histogram.durationS() * speed_of_sound_m_s;
    if (!(tail[0] > 0.0)) continue;
    bool started = false;
    for (std::size_t n = 0; n < histogram.bins(); ++n) {
      const double down_db = 10.0 * std::log10(tail[0] / std::max(tail[n], 1e-300));
      const double at_m = static_cast<double>(n) * histogram.binS() * speed_of_sound_m_s;
      if (!started && down_db >= 5.0) {
        from_m[k] = at_m;
        started = true;
      }
      if (down_db >= 35.0) {
        to_m[k] = at_m;
        break;
      }
    }
  }
}

namespace {

double effectiveCount(double sum, double sum_of_squares) {
  return sum_of_squares > 0.0 ? sum * sum / sum_of_squares : 0.0;
}

}  // namespace

std::uint64_t meshFingerprint(const TriangleMesh& mesh) {
  std::uint64_t h = mixBits(mesh.triangles.size());
  const auto add = [&h](std::uint64_t bits) { h = mixBits(h ^ bits); };
  for (const Eigen::Vector3d& v : mesh.vertices) {
    for (int i = 0; i < 3; ++i) {
      std::uint64_t bits = 0;
      std::memcpy(&bits, &v[i], sizeof bits);
      add(bits);
    }
  }
  for (const auto& t : mesh.triangles) {
    for (int i : t) add(static_cast<std::uint64_t>(i));
  }
  return h;
}

std::size_t PathLedger::bytes() const {
  std::size_t n = 0;
  for (const auto& c : chunks) n += c.size() * sizeof(LedgerEvent);
  return n + (reflectance.size() + scattering.size()) * sizeof(OctaveBandValues);
}

LedgerReplay replayLedger(const PathLedger& ledger, const AcousticScene& scene, const PropagationModel& model,
                          const LedgerReplayOptions& options) {
  LedgerReplay out;
  const TriangleMesh& mesh = scene.mesh();
  if (mesh.triangleCount() != ledger.reflectance.size() || meshFingerprint(mesh) != ledger.mesh_fingerprint) {
    out.why_not = "the scene has other triangles than the traced one";
    return out;
  }
  if (std::abs(model.speed_of_sound_m_s - ledger.speed_of_sound_m_s) > 1e-9 * ledger.speed_of_sound_m_s) {
    out.why_not = "the speed of sound differs from the traced model's";
    return out;
  }
  std::vector<OctaveBandValues> reflectance(mesh.triangleCount());
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const AcousticMaterial& m = scene.material(t);
    for (int k = 0; k < kOctaveBandCount; ++k) {
      if (m.scattering[k] != ledger.scattering[t][k]) {
        out.why_not = "a surface scatters differently from the traced model";
        return out;
      }
      reflectance[t][k] = 1.0 - m.absorption[k];
      // A surface that absorbed everything ended the traced paths there: the new model's
      // paths beyond it were never followed.
      if (ledger.reflectance[t][k] <= 0.0 && reflectance[t][k] > 0.0) {
        out.why_not = "a surface the traced model made fully absorbing reflects";
        return out;
      }
    }
  }
  if (!ledger.directivity.isOmni()) {
    // Directions the traced source did not send energy into were faded at once.
    for (const auto& chunk : ledger.chunks) {
      for (const LedgerEvent& e : chunk) {
        if (e.kind() != LedgerEvent::kLaunch || e.factor > 0.0f) continue;
        const Eigen::Vector3d direction(e.direction[0], e.direction[1], e.direction[2]);
        if (model.directivity.pressureGain(direction) != 0.0) {
          out.why_not = "the new source radiates where the traced one was silent";
          return out;
        }
      }
    }
  }
  const int threads = options.threads > 0 ? options.threads : std::max(1, ledger.threads);
  const AirLossTable air(model.air_attenuation_per_m, ledger.bin_s * ledger.speed_of_sound_m_s, ledger.bins);
  ChunkReplay replay{ledger, reflectance, model, air};
  out.histogram = replayAll(ledger, replay, threads);
  // The rays' energies where each estimate's decay is read: replayed in the replay's range,
  // with the traced walls in the traced one's.
  RayShares shares(ledger.ray_count);
  for (auto& s : shares) {
    for (auto& band : s) band = {0.0, 0.0};
  }
  replay.shares = &shares;
  decayRange(out.histogram, ledger.speed_of_sound_m_s, replay.from_m, replay.to_m);
  replay.counted_from_m = std::numeric_limits<double>::infinity();
  replay.counted_to_m = 0.0;
  for (int k = 0; k < kOctaveBandCount; ++k) {
    replay.counted_from_m = std::min({replay.counted_from_m, replay.from_m[k], ledger.decay_from_m[k]});
    replay.counted_to_m = std::max({replay.counted_to_m, replay.to_m[k], ledger.decay_to_m[k]});
  }
  replayAll(ledger, replay, threads);  // each ray is in one chunk: no two threads share a count
  for (int k = 0; k < kOctaveBandCount; ++k) {
    double sum[2] = {0.0, 0.0}, squares[2] = {0.0, 0.0};
    for (const auto& s : shares) {
      for (int m = 0; m < 2; ++m) {
        sum[m] += s[k][m];
        squares[m] += s[k][m] * s[k][m];
      }
    }
    const double traced = effectiveCount(sum[1], squares[1]);
    out.effective_share[k] = traced > 0.0 ? effectiveCount(sum[0], squares[0]) / traced : 1.0;
  }
  for (int k = 0; k < kOctaveBandCount; ++k) {
    if (out.effective_share[k] < options.min_effective_share) {
      const double nominal_hz = standardBands(BandResolution::kOctave)[static_cast<std::size_t>(k)].nominal_hz;
      out.why_not = "too few effective rays in the " + std::to_string(static_cast<int>(std::lround(nominal_hz))) +
                    " Hz band's decay (" + std::to_string(static_cast<int>(std::lround(100.0 * out.effective_share[k]))) +
                    " % of the traced model's)";
      out.histogram = EnergyHistogram();
      return out;
    }
  }
  out.replayed = true;
  return out;
}

}  // namespace room_reverb::core
