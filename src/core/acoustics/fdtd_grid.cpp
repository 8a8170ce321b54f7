#include "room_reverb/acoustics/fdtd_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "room_reverb/common/error.h"

namespace room_reverb::core {
namespace {

constexpr std::array<std::array<int, 3>, 6> kFaceSteps{{{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}}};

// Distances along origin + t direction at which the line crosses a surface, ascending.
std::vector<double> crossings(const EmbreeScene& geometry, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                              double length_m) {
  std::vector<double> out;
  double from = 0.0;
  for (;;) {
    const RayHit hit = geometry.intersect(origin, direction, from, length_m);
    if (!hit.hit) break;
    out.push_back(hit.distance_m);
    // The next triangle along; one sharing this crossing's edge is the same crossing.
    from = hit.distance_m + 1e-6;
  }
  return out;
}

// Marks, along one grid line, the cells whose centre lies after an odd number of crossings.
void parityAlongLine(const EmbreeScene& geometry, const Eigen::Vector3d& start, const Eigen::Vector3d& axis, double spacing_m,
                     int count, std::vector<std::uint8_t>& inside, std::size_t first, std::size_t stride) {
  // `start` is the centre of cell 0 of the line, which lies outside the mesh's bounds.
  const std::vector<double> hits = crossings(geometry, start, axis, spacing_m * count);
  std::size_t passed = 0;
  for (int c = 0; c < count; ++c) {
    const double at = spacing_m * c;
    while (passed < hits.size() && hits[passed] < at) ++passed;
    inside[first + stride * static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(passed % 2);
  }
}

}  // namespace

std::size_t FdtdGrid::airCellCount() const {
  return static_cast<std::size_t>(std::count(air.begin(), air.end(), std::uint8_t{1}));
}

double FdtdGrid::boundaryFaceAreaM2() const {
  std::size_t faces = 0;
  for (const BoundaryCell& cell : boundary) faces += static_cast<std::size_t>(6 - cell.air_neighbours);
  return static_cast<double>(faces) * spacing_m * spacing_m;
}

double FdtdGrid::correctedBoundaryAreaM2() const {
  double weight = 0.0;
  for (const BoundaryCell& cell : boundary) {
    for (int f = 0; f < 6; ++f) {
      if (cell.face_material[f] >= 0) weight += cell.face_weight[f];
    }
  }
  return weight * spacing_m * spacing_m;
}

FdtdGrid voxelizeScene(const AcousticScene& scene, double spacing_m) {
  if (!(spacing_m > 0.0) || !std::isfinite(spacing_m)) throw InputError("the wave solver's grid spacing must be positive");
  const EmbreeScene& geometry = scene.geometry();
  const Eigen::Vector3d lo = geometry.boundsMin(), hi = geometry.boundsMax();
  FdtdGrid grid;
  grid.spacing_m = spacing_m;
  // Cell 1's centre half a cell inside the bounds: an axis-aligned wall then lies on cell
  // faces when the room's size is a whole number of cells.
  grid.origin_m = lo - Eigen::Vector3d::Constant(0.5 * spacing_m);
  const Eigen::Vector3d cells = ((hi - lo) / spacing_m).array().ceil();
  const double total = (cells.array() + 2.0).prod();
  if (!(total < 2147483648.0)) throw InputError("the wave solver's grid would have " + std::to_string(total) + " cells (at most 2^31)");
  grid.nx = static_cast<int>(cells.x()) + 2;
  grid.ny = static_cast<int>(cells.y()) + 2;
  grid.nz = static_cast<int>(cells.z()) + 2;
  const std::size_t n = static_cast<std::size_t>(grid.nx) * static_cast<std::size_t>(grid.ny) * static_cast<std::size_t>(grid.nz);
  std::vector<std::uint8_t> along_x(n, 0), along_y(n, 0);
  const std::size_t nx = static_cast<std::size_t>(grid.nx);
  for (int k = 1; k + 1 < grid.nz; ++k) {
    for (int j = 1; j + 1 < grid.ny; ++j) {
      parityAlongLine(geometry, grid.centre(0, j, k), Eigen::Vector3d::UnitX(), spacing_m, grid.nx, along_x, grid.index(0, j, k), 1);
    }
    for (int i = 1; i + 1 < grid.nx; ++i) {
      parityAlongLine(geometry, grid.centre(i, 0, k), Eigen::Vector3d::UnitY(), spacing_m, grid.ny, along_y, grid.index(i, 0, k), nx);
    }
  }
  grid.air.assign(n, 0);
  for (int k = 1; k + 1 < grid.nz; ++k) {
    for (int j = 1; j + 1 < grid.ny; ++j) {
      for (int i = 1; i + 1 < grid.nx; ++i) {
        const std::size_t c = grid.index(i, j, k);
        const bool inside = along_x[c] == along_y[c] ? along_x[c] != 0 : scene.isInside(grid.centre(i, j, k));
        // An object's interior lies inside the room's mesh by parity too when its faces are
        // part of the mesh, so the parity already leaves it out.
        grid.air[c] = inside ? 1 : 0;
      }
    }
  }
  // Boundary cells and the material behind each solid face.
  for (int k = 1; k + 1 < grid.nz; ++k) {
    for (int j = 1; j + 1 < grid.ny; ++j) {
      for (int i = 1; i + 1 < grid.nx; ++i) {
        const std::size_t c = grid.index(i, j, k);
        if (!grid.air[c]) continue;
        FdtdGrid::BoundaryCell cell;
        cell.cell = static_cast<std::uint32_t>(c);
        cell.air_neighbours = 0;
        std::array<bool, 6> solid{};
        for (int f = 0; f < 6; ++f) {
          const std::size_t neighbour = grid.index(i + kFaceSteps[f][0], j + kFaceSteps[f][1], k + kFaceSteps[f][2]);
          solid[f] = grid.air[neighbour] == 0;
          if (!solid[f]) ++cell.air_neighbours;
        }
        if (cell.air_neighbours == 6) continue;
        const Eigen::Vector3d centre = grid.centre(i, j, k);
        std::array<RayHit, 6> hits;
        int nearest = -1;
        for (int f = 0; f < 6; ++f) {
          const Eigen::Vector3d direction(kFaceSteps[f][0], kFaceSteps[f][1], kFaceSteps[f][2]);
          hits[f] = geometry.intersect(centre, direction, 1e-9);
          if (hits[f].hit && (nearest < 0 || hits[f].distance_m < hits[nearest].distance_m)) nearest = f;
        }
        for (int f = 0; f < 6; ++f) {
          if (!solid[f]) continue;
          const RayHit& hit = hits[f].hit && hits[f].distance_m <= 2.0 * spacing_m ? hits[f] : hits[std::max(nearest, 0)];
          cell.face_material[f] = hit.hit ? scene.mesh().triangle_material[hit.triangle] : 0;
          if (hit.hit) cell.face_weight[f] = static_cast<float>(1.0 / hit.normal.lpNorm<1>());
        }
        grid.boundary.push_back(cell);
      }
    }
  }
  return grid;
}

}  // namespace room_reverb::core
