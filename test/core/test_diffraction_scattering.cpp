// The scattering of a surface's finite size (Rindel's strip model): the surfaces found in
// a mesh, the specular share against the formula worked by hand, and its effect on image
// sources and on a decay.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/diffraction_scattering.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/acoustics/room_simulation.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"
#include "shoebox.h"

using namespace room_reverb::core;
using room_reverb::test::noAir;

namespace {

constexpr double kC = 343.0;

// Quads in the plane z = 0 (normal +z), each as two triangles, material per quad.
TriangleMesh flatQuads(const std::vector<std::array<double, 4>>& quads, const std::vector<int>& materials) {
  TriangleMesh mesh;
  mesh.material_names = {"a", "b"};
  for (std::size_t q = 0; q < quads.size(); ++q) {
    const auto [x0, y0, x1, y1] = quads[q];
    const int base = static_cast<int>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}});
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
    mesh.triangle_material.insert(mesh.triangle_material.end(), 2, materials[q]);
  }
  return mesh;
}

std::vector<SurfaceExtent> patchesOf(const TriangleMesh& mesh, std::vector<std::size_t>& triangle_patch) {
  return surfaceExtents(mesh, std::vector<std::size_t>(mesh.triangleCount(), 0), triangle_patch);
}

}  // namespace

TEST(DiffractionScattering, AWallOfTwoMaterialsIsOneSurfaceAndAPieceApartIsAnother) {
  // A 4 x 2 m wall of two materials side by side, and a 1 x 1 m piece 3 m away in the
  // same plane. The quads do not share vertex indices: only positions join them.
  const TriangleMesh mesh = flatQuads({{0, 0, 2, 2}, {2, 0, 4, 2}, {7, 0, 8, 1}}, {0, 1, 0});
  std::vector<std::size_t> triangle_patch;
  const std::vector<SurfaceExtent> patches = patchesOf(mesh, triangle_patch);
  ASSERT_EQ(patches.size(), 2u);
  for (std::size_t t = 0; t < 4; ++t) EXPECT_EQ(triangle_patch[t], triangle_patch[0]);
  EXPECT_NE(triangle_patch[4], triangle_patch[0]);
  const SurfaceExtent& wall = patches[triangle_patch[0]];
  EXPECT_NEAR(wall.area_m2, 8.0, 1e-9);
  EXPECT_NEAR(wall.width_u_m, 4.0, 1e-9);
  EXPECT_NEAR(wall.width_v_m, 2.0, 1e-9);
  EXPECT_NEAR(std::abs(wall.axis_u.x()), 1.0, 1e-9);  // the long side along x
  EXPECT_NEAR(patches[triangle_patch[4]].width_u_m, 1.0, 1e-9);
}

TEST(DiffractionScattering, AnIrregularSurfaceKeepsItsArea) {
  // An L of three unit squares: its extents are 2 x 2, its area 3.
  const TriangleMesh mesh = flatQuads({{0, 0, 1, 1}, {1, 0, 2, 1}, {0, 1, 1, 2}}, {0, 0, 0});
  std::vector<std::size_t> triangle_patch;
  const std::vector<SurfaceExtent> patches = patchesOf(mesh, triangle_patch);
  ASSERT_EQ(patches.size(), 1u);
  EXPECT_NEAR(patches[0].area_m2, 3.0, 1e-9);
  EXPECT_NEAR(patches[0].width_u_m * patches[0].width_v_m, 3.0, 1e-9);
}

TEST(DiffractionScattering, TheSpecularShareFollowsRindelsLimitFrequency) {
  SurfaceExtent patch;  // 4 m along x, 2 m along y
  patch.width_u_m = 4.0;
  patch.width_v_m = 2.0;
  patch.area_m2 = 8.0;
  const Eigen::Vector3d normal_incidence(0, 0, -1);
  const double a_star = characteristicDistance(2.0, 2.0);
  EXPECT_DOUBLE_EQ(a_star, 2.0);
  // f_g = c a* / (2 a^2): 85.75 Hz for the 2 m side, 21.4 Hz for the 4 m one.
  EXPECT_NEAR(specularShare(patch, normal_incidence, a_star, 42.875, kC), 0.5, 1e-12);
  EXPECT_NEAR(specularShare(patch, normal_incidence, a_star, 10.71875, kC), 0.5 * 0.125, 1e-12);
  EXPECT_DOUBLE_EQ(specularShare(patch, normal_incidence, a_star, 100.0, kC), 1.0);
  // At 60 degrees in the plane of the 2 m side the wave sees 1 m: f_g = 343 Hz.
  const Eigen::Vector3d oblique(0, std::sin(M_PI / 3), -std::cos(M_PI / 3));
  EXPECT_NEAR(specularShare(patch, oblique, a_star, 171.5, kC), 0.5, 1e-12);
  // The same angle in the plane of the 4 m side: it sees 2 m of it and the 2 m side
  // whole, so both sides halve the share.
  const Eigen::Vector3d oblique_x(std::sin(M_PI / 3), 0, -std::cos(M_PI / 3));
  EXPECT_NEAR(specularShare(patch, oblique_x, a_star, 42.875, kC), 0.25, 1e-12);
  // Grazing: nothing is left specular.
  EXPECT_LT(specularShare(patch, Eigen::Vector3d(0, 1, 0), a_star, 1000.0, kC), 1e-100);
}

TEST(DiffractionScattering, OnlySmallSurfacesAndLowBandsGainScattering) {
  OctaveBandValues material;
  material.fill(0.1);
  SurfaceExtent large, small;
  large.width_u_m = large.width_v_m = 100.0;
  small.width_u_m = small.width_v_m = 0.6;
  const Eigen::Vector3d incident = Eigen::Vector3d(0.3, 0.2, -1.0).normalized();
  const OctaveBandValues on_large = withDiffractionScattering(material, large, incident, 3.0, kC);
  const OctaveBandValues on_small = withDiffractionScattering(material, small, incident, 3.0, kC);
  for (int b = 0; b < kOctaveBandCount; ++b) EXPECT_NEAR(on_large[b], 0.1, 1e-12) << b;
  EXPECT_GT(on_small[0], 0.95);  // 63 Hz off a 0.6 m panel
  for (int b = 1; b < kOctaveBandCount; ++b) EXPECT_LE(on_small[b], on_small[b - 1]) << b;
  EXPECT_NEAR(on_small[kOctaveBandCount - 1], 0.1, 1e-12);  // 16 kHz: a mirror
}

TEST(DiffractionScattering, AnImageSourceLosesWhatItsWallsSizeDiffracts) {
  // A 1.5 x 1 x 2.4 m box, rigid and smooth: the first-order image in the floor (z = 0)
  // keeps, per band, the square root of Rindel's share for that wall, worked out here
  // from the geometry alone (0.40 at 63 Hz, 0.74 at 125 Hz, 1 from 250 Hz).
  const Eigen::Vector3d size(1.5, 1.0, 2.4);
  const AcousticScene scene(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(0.0, 0.0));
  const Eigen::Vector3d source(0.5, 0.4, 1.5), listener(1.1, 0.7, 1.1);
  const PropagationModel model = PropagationModel::from(noAir(), {});
  ImageSourceOptions plain, diffracting;
  plain.max_order = diffracting.max_order = 1;
  diffracting.diffraction_scattering = true;
  const std::vector<SpecularPath> without = computeImageSources(scene, source, listener, model, plain);
  const std::vector<SpecularPath> with = computeImageSources(scene, source, listener, model, diffracting);
  ASSERT_EQ(without.size(), 7u);
  ASSERT_EQ(with.size(), 7u);
  const Eigen::Vector3d image(source.x(), source.y(), -source.z());
  const double t = source.z() / (source.z() + listener.z());
  const Eigen::Vector3d point = source + t * (Eigen::Vector3d(listener.x(), listener.y(), 0) - Eigen::Vector3d(source.x(), source.y(), 0)) -
                                Eigen::Vector3d(0, 0, source.z());
  const double d1 = (point - source).norm(), d2 = (listener - point).norm();
  const double a_star = 2 * d1 * d2 / (d1 + d2);
  const Eigen::Vector3d incident = (point - source).normalized();
  const std::vector<FrequencyBand> bands = standardBands(BandResolution::kOctave);
  int found = 0;
  for (std::size_t k = 0; k < with.size(); ++k) {
    ASSERT_NEAR(with[k].distance_m, without[k].distance_m, 1e-12);
    if ((with[k].image_position - image).norm() > 1e-9) {
      if (with[k].order == 0) {
        for (int b = 0; b < kOctaveBandCount; ++b) EXPECT_DOUBLE_EQ(with[k].pressure_gain[b], without[k].pressure_gain[b]);
      }
      continue;
    }
    ++found;
    for (int b = 0; b < kOctaveBandCount; ++b) {
      const double f = bands[static_cast<std::size_t>(b)].center_hz;
      const double c = model.speed_of_sound_m_s;
      const double seen_x = 1.5 * std::sqrt(1 - incident.x() * incident.x());
      const double seen_y = 1.0 * std::sqrt(1 - incident.y() * incident.y());
      const double share = std::min(1.0, 2 * f * seen_x * seen_x / (c * a_star)) *
                           std::min(1.0, 2 * f * seen_y * seen_y / (c * a_star));
      EXPECT_NEAR(with[k].pressure_gain[b] / without[k].pressure_gain[b], std::sqrt(share), 1e-6) << f << " Hz";
    }
    EXPECT_LT(with[k].pressure_gain[0], 0.45 * without[k].pressure_gain[0]);  // 63 Hz
    EXPECT_DOUBLE_EQ(with[k].pressure_gain[2], without[k].pressure_gain[2]);  // 250 Hz
  }
  EXPECT_EQ(found, 1);
}

// A small room whose absorption is all on the floor, with smooth walls: without
// scattering the sound that runs between the hard walls lasts; the walls' finite size
// scatters the low bands into the floor, and the high bands stay as they were.
TEST(DiffractionScattering, ASmallSmoothRoomsLowBandsDecayFasterAndItsHighBandsDoNot) {
  TriangleMesh mesh = room_reverb::test::shoeboxMesh({3.0, 2.2, 2.5}, "hard");
  mesh.material_names.push_back("absorbing");
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (mesh.normal(t).z() > 0.9) mesh.triangle_material[t] = 1;  // the floor
  }
  MaterialLibrary library = room_reverb::test::uniformLibrary(0.02, 0.0, "hard");
  AcousticMaterial absorbing;
  absorbing.name = "absorbing";
  absorbing.absorption.fill(0.7);
  absorbing.scattering.fill(0.0);
  absorbing.source = "test";
  library.add(absorbing);
  const AcousticScene scene(mesh, library);
  SimulationSettings settings;
  settings.air = noAir();
  settings.duration_s = 2.0;
  settings.ambisonic_order = 0;
  settings.rays.ray_count = 20000;
  settings.rays.threads = 2;
  const Eigen::Vector3d source(0.8, 0.7, 1.4), listener(2.1, 1.5, 1.2);
  const SimulationResult plain = simulateRoom(scene, source, listener, settings);
  settings.diffraction_scattering = true;
  const SimulationResult diffracting = simulateRoom(scene, source, listener, settings);
  const MetricsReport a = computeRoomAcousticParameters(plain.impulse_response.channels[0], 48000.0);
  const MetricsReport b = computeRoomAcousticParameters(diffracting.impulse_response.channels[0], 48000.0);
  for (std::size_t band = 1; band <= 6; ++band) {
    ASSERT_TRUE(a.bands[band].t20_s && b.bands[band].t20_s) << a.bands[band].reason << b.bands[band].reason;
    std::cout << "[ measured ] " << a.bands[band].nominal_hz << " Hz: T20 " << *a.bands[band].t20_s << " s, with diffraction "
              << *b.bands[band].t20_s << " s\n";
  }
  EXPECT_LT(*b.bands[1].t20_s, 0.8 * *a.bands[1].t20_s);   // 125 Hz
  EXPECT_NEAR(*b.bands[6].t20_s / *a.bands[6].t20_s, 1.0, 0.06);  // 4 kHz: only near grazing
}
