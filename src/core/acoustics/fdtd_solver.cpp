#include "room_reverb/acoustics/fdtd_solver.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cmath>
#include <mutex>
#include <sstream>
#include <thread>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kLambdaSquared = 1.0 / 3.0;  // Courant number squared at the limit

// Threads meet three times per time step, some 20 000 times a second of response: a
// condition variable's wake-up (tens of microseconds) would cost more than a step's work
// on a small grid, so they spin first; on a machine busy with other work the partner may
// not be running at all, and a waiter that has spun for long sleeps on the condition
// variable instead of taking the core from it.
class SpinBarrier {
 public:
  explicit SpinBarrier(int parties) : parties_(parties) {}
  void wait() {
    const int generation = generation_.load(std::memory_order_acquire);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == parties_) {
      arrived_.store(0, std::memory_order_relaxed);
      {
        const std::lock_guard<std::mutex> lock(mutex_);
        generation_.fetch_add(1, std::memory_order_acq_rel);
      }
      cv_.notify_all();
      return;
    }
    for (int spins = 0; spins < kSpins; ++spins) {
      if (generation_.load(std::memory_order_acquire) != generation) return;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != generation; });
  }

 private:
  static constexpr int kSpins = 200000;  // about 0.1-0.5 ms
  const int parties_;
  std::atomic<int> arrived_{0};
  std::atomic<int> generation_{0};
  std::mutex mutex_;
  std::condition_variable cv_;
};

// The eight cells around `point` and their trilinear weights.
struct Trilinear {
  std::array<std::size_t, 8> cells{};
  std::array<double, 8> weights{};
};

// `reach` 1: the cells themselves must be air; 2: their six neighbours too (for a
// gradient).
Trilinear trilinearAt(const FdtdGrid& grid, const Eigen::Vector3d& point, const char* what, int reach) {
  const Eigen::Vector3d u = (point - grid.origin_m) / grid.spacing_m;
  const Eigen::Vector3d base = u.array().floor();
  const Eigen::Vector3d frac = u - base;
  Trilinear t;
  for (int corner = 0; corner < 8; ++corner) {
    const int i = static_cast<int>(base.x()) + (corner & 1), j = static_cast<int>(base.y()) + (corner >> 1 & 1),
              k = static_cast<int>(base.z()) + (corner >> 2 & 1);
    const int margin = reach - 1;
    bool clear = i - margin >= 0 && j - margin >= 0 && k - margin >= 0 && i + margin < grid.nx && j + margin < grid.ny &&
                 k + margin < grid.nz && grid.air[grid.index(i, j, k)];
    for (int axis = 0; clear && margin > 0 && axis < 3; ++axis) {
      for (int side = -1; side <= 1; side += 2) {
        const int step[3] = {axis == 0 ? side : 0, axis == 1 ? side : 0, axis == 2 ? side : 0};
        clear = clear && grid.air[grid.index(i + step[0], j + step[1], k + step[2])];
      }
    }
    if (!clear) {
      std::ostringstream os;
      os << what << " (" << point.x() << ", " << point.y() << ", " << point.z() << ") m is within " << reach
         << " grid cell(s) (" << grid.spacing_m << " m each) of a surface or outside the room: the wave solver needs air around it";
      throw InputError(os.str());
    }
    t.cells[corner] = grid.index(i, j, k);
    t.weights[corner] = ((corner & 1) ? frac.x() : 1.0 - frac.x()) * ((corner >> 1 & 1) ? frac.y() : 1.0 - frac.y()) *
                        ((corner >> 2 & 1) ? frac.z() : 1.0 - frac.z());
  }
  return t;
}

// The update of every air cell as if it had six air neighbours (solid cells hold 0), for
// the z-layers [k_begin, k_end): `previous` becomes the next field in place.
void interiorUpdate(const FdtdGrid& grid, const std::vector<float>& current, std::vector<float>& previous, int k_begin,
                    int k_end) {
  const std::size_t nx = static_cast<std::size_t>(grid.nx), nxy = nx * static_cast<std::size_t>(grid.ny);
  const float third = static_cast<float>(kLambdaSquared);
  const float* p = current.data();
  float* q = previous.data();
  const std::uint8_t* air = grid.air.data();
  for (int k = k_begin; k < k_end; ++k) {
    for (int j = 1; j + 1 < grid.ny; ++j) {
      const std::size_t row = grid.index(0, j, k);
      for (std::size_t c = row + 1; c + 1 < row + nx; ++c) {
        const float sum = p[c - 1] + p[c + 1] + p[c - nx] + p[c + nx] + p[c - nxy] + p[c + nxy];
        q[c] = static_cast<float>(air[c]) * (third * sum - q[c]);
      }
    }
  }
}

}  // namespace

double fdtdSpacingFor(double max_frequency_hz, double cells_per_wavelength, double speed_of_sound_m_s) {
  if (!(max_frequency_hz > 0.0) || !(cells_per_wavelength >= 2.0)) {
    throw InputError("the wave solver needs a positive top frequency and at least 2 cells per wavelength");
  }
  return speed_of_sound_m_s / (max_frequency_hz * cells_per_wavelength);
}

double fdtdAxialPhaseSpeedRatio(double cells_per_wavelength) {
  const double lambda = std::sqrt(kLambdaSquared);
  const double kh = 2.0 * kPi / cells_per_wavelength;
  // sin(omega dt / 2) = lambda sin(k h / 2) along an axis.
  return 2.0 * std::asin(lambda * std::sin(0.5 * kh)) / (lambda * kh);
}

FdtdResponse solveWaveField(const FdtdGrid& grid, const Eigen::Vector3d& source, const Eigen::Vector3d& listener,
                            const std::vector<double>& face_admittance, const FdtdOptions& options) {
  if (!(options.duration_s > 0.0)) throw InputError("the wave solver's duration must be positive");
  if (!(options.speed_of_sound_m_s > 0.0)) throw InputError("the wave solver needs a positive speed of sound");
  for (double beta : face_admittance) {
    if (!(beta >= 0.0) || !std::isfinite(beta)) throw InputError("a wall admittance must be finite and 0 or more");
  }
  const Trilinear at_source = trilinearAt(grid, source, "source", 1);
  const Trilinear at_listener = trilinearAt(grid, listener, "listener", 2);
  const double h = grid.spacing_m;
  const double lambda = std::sqrt(kLambdaSquared);
  const double dt = lambda * h / options.speed_of_sound_m_s;

  // Per boundary cell: the correction (6 - K) lambda^2 that turns the interior update
  // into its own, and its loss g.
  const std::size_t boundary_count = grid.boundary.size();
  std::vector<std::uint32_t> boundary_cell(boundary_count);
  std::vector<float> missing(boundary_count), loss(boundary_count);
  for (std::size_t b = 0; b < boundary_count; ++b) {
    const FdtdGrid::BoundaryCell& cell = grid.boundary[b];
    boundary_cell[b] = cell.cell;
    missing[b] = static_cast<float>((6 - cell.air_neighbours) * kLambdaSquared);
    double beta_sum = 0.0;
    for (int f = 0; f < 6; ++f) {
      const int m = cell.face_material[f];
      if (m < 0) continue;
      if (static_cast<std::size_t>(m) >= face_admittance.size()) throw InputError("a wall's material has no admittance");
      beta_sum += face_admittance[static_cast<std::size_t>(m)] * cell.face_weight[f];
    }
    loss[b] = static_cast<float>(0.5 * lambda * beta_sum);
  }

  FdtdResponse response;
  response.sample_rate_hz = 1.0 / dt;
  response.steps = static_cast<std::size_t>(std::ceil(options.duration_s / dt));
  response.air_cells = grid.airCellCount();
  response.pressure.assign(response.steps, 0.0);
  for (auto& channel : response.velocity) channel.assign(response.steps, 0.0);

  std::vector<float> current(grid.cellCount(), 0.0f), previous(grid.cellCount(), 0.0f);
  // p- of the boundary cells, which the in-place update overwrites: each step's boundary
  // pass keeps p of its cells for the next.
  std::vector<float> saved(boundary_count, 0.0f);
  // A unit-area impulse A = 1/dt at t = 0: p+ gains 4 pi lambda^2 A / h at the source
  // (the scheme's form of c^2 dt^2 4 pi A delta(x), delta(x) ~ 1/h^3).
  const double injection = 4.0 * kPi * kLambdaSquared / (h * dt);
  const std::size_t nx = static_cast<std::size_t>(grid.nx), nxy = nx * static_cast<std::size_t>(grid.ny);
  Eigen::Vector3d gradient_sum = Eigen::Vector3d::Zero();

  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = std::max(1, std::min(options.threads > 0 ? options.threads : hardware, grid.nz - 2));
  SpinBarrier barrier(threads);
  auto work = [&](int t) {
    const int layers = grid.nz - 2;
    const int k_begin = 1 + layers * t / threads, k_end = 1 + layers * (t + 1) / threads;
    const std::size_t b_begin = boundary_count * static_cast<std::size_t>(t) / static_cast<std::size_t>(threads);
    const std::size_t b_end = boundary_count * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(threads);
    for (std::size_t n = 0; n < response.steps; ++n) {
      interiorUpdate(grid, current, previous, k_begin, k_end);
      barrier.wait();
      for (std::size_t b = b_begin; b < b_end; ++b) {
        const std::uint32_t c = boundary_cell[b];
        previous[c] = (previous[c] + missing[b] * current[c] + loss[b] * saved[b]) / (1.0f + loss[b]);
        saved[b] = current[c];
      }
      barrier.wait();
      if (t == 0) {
        // Read the listener at time n (the field in `current`), then inject and swap.
        double p = 0.0;
        Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
        for (int corner = 0; corner < 8; ++corner) {
          const std::size_t c = at_listener.cells[corner];
          const double w = at_listener.weights[corner];
          p += w * current[c];
          gradient += w * 0.5 * Eigen::Vector3d(current[c + 1] - current[c - 1], current[c + nx] - current[c - nx],
                                                current[c + nxy] - current[c - nxy]);
        }
        response.pressure[n] = p;
        // X = -rho c v, and rho dv/dt = -grad p: X = c dt sum(grad p) = lambda sum(h grad p).
        gradient_sum += gradient;
        for (int axis = 0; axis < 3; ++axis) response.velocity[static_cast<std::size_t>(axis)][n] = lambda * gradient_sum[axis];
        if (n == 0) {
          for (int corner = 0; corner < 8; ++corner) {
            previous[at_source.cells[corner]] += static_cast<float>(injection * at_source.weights[corner]);
          }
        }
        current.swap(previous);
      }
      barrier.wait();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& thread : pool) thread.join();
  return response;
}

}  // namespace room_reverb::core
