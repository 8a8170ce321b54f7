// Image sources in a shoebox against the analytic image lattice (Allen & Berkley 1979).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <random>

#include "room_reverb/acoustics/acoustic_scene.h"
#include "room_reverb/acoustics/edge_diffraction.h"
#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/acoustics/image_sources.h"
#include "room_reverb/acoustics/impulse_response_synthesis.h"
#include "room_reverb/audio/fft.h"
#include "shoebox.h"
#include "test_files.h"
#include "test_rooms.h"

using namespace room_reverb::core;

namespace {

struct AnalyticImage {
  Eigen::Vector3d position;
  int order;
};

std::vector<AnalyticImage> shoeboxImages(const Eigen::Vector3d& size, const Eigen::Vector3d& source, int max_order) {
  std::vector<AnalyticImage> images;
  for (int nx = -2; nx <= 2; ++nx) for (int ny = -2; ny <= 2; ++ny) for (int nz = -2; nz <= 2; ++nz)
    for (int px = 0; px < 2; ++px) for (int py = 0; py < 2; ++py) for (int pz = 0; pz < 2; ++pz) {
      const int order = std::abs(2 * nx - px) + std::abs(2 * ny - py) + std::abs(2 * nz - pz);
      if (order > max_order) continue;
      const Eigen::Vector3d p((1 - 2 * px) * source.x() + 2 * nx * size.x(),
                              (1 - 2 * py) * source.y() + 2 * ny * size.y(),
                              (1 - 2 * pz) * source.z() + 2 * nz * size.z());
      images.push_back({p, order});
    }
  return images;
}

}  // namespace

TEST(ImageSources, ShoeboxMatchesTheAnalyticLatticeToOrderThree) {
  const Eigen::Vector3d size(6.2, 4.3, 2.9);
  const Eigen::Vector3d source(1.7, 1.1, 1.3), listener(4.4, 3.05, 1.6);
  const double alpha = 0.2;
  const AcousticScene scene(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(alpha, 0.0));
  AirConditions no_air;
  no_air.enabled = false;
  const PropagationModel model = PropagationModel::from(no_air, {});
  const auto paths = computeImageSources(scene, source, listener, model);
  const auto expected = shoeboxImages(size, source, 3);
  ASSERT_EQ(expected.size(), 63u);  // 1 + 6 + 18 + 38
  EXPECT_EQ(paths.size(), expected.size());
  const double sample_s = 1.0 / 48000.0;
  for (const auto& image : expected) {
    const double distance = (image.position - listener).norm();
    const double delay = distance / model.speed_of_sound_m_s;
    const double amplitude = std::pow(1.0 - alpha, 0.5 * image.order) / distance;
    const SpecularPath* match = nullptr;
    for (const auto& path : paths) {
      if ((path.image_position - image.position).norm() < 1e-6) match = &path;
    }
    ASSERT_NE(match, nullptr) << "missing image of order " << image.order << " at " << image.position.transpose();
    EXPECT_EQ(match->order, image.order);
    EXPECT_LT(std::abs(match->delay_s - delay), 0.1 * sample_s);
    for (int b = 0; b < kOctaveBandCount; ++b) EXPECT_NEAR(match->pressure_gain[b] / amplitude, 1.0, 0.01);
    EXPECT_NEAR((match->arrival_direction - (image.position - listener).normalized()).norm(), 0.0, 1e-9);
  }
}

// An order whose search would run for hours is refused up front, with the order that fits.
TEST(ImageSources, AnOrderBeyondTheCandidateBudgetIsRefusedUpFront) {
  const AcousticScene scene(room_reverb::test::shoeboxMesh({6.2, 4.3, 2.9}), room_reverb::test::uniformLibrary(0.2, 0.0));
  const Eigen::Vector3d source(1.7, 1.1, 1.3), listener(4.4, 3.05, 1.6);
  // Orders 0 and 1: the source itself, and its image in each of the six walls.
  EXPECT_EQ(estimatedImageCandidates(scene, source, listener, 0), 1.0);
  EXPECT_EQ(estimatedImageCandidates(scene, source, listener, 1), 7.0);
  // Order 3 is counted: its candidates include the 63 real images.
  EXPECT_GE(estimatedImageCandidates(scene, source, listener, 3), 63.0);
  const PropagationModel model = PropagationModel::from(AirConditions{}, {});
  ImageSourceOptions options;
  options.max_order = 40;
  room_reverb::test::expectInputError([&] { computeImageSources(scene, source, listener, model, options); },
                                      {"image-source order 40", "candidate paths", "use order"});
  // Within the budget the same room searches as before.
  options.max_order = 3;
  EXPECT_EQ(computeImageSources(scene, source, listener, model, options).size(), 63u);
  options.max_order = 4;
  options.max_candidates = estimatedImageCandidates(scene, source, listener, 3);
  room_reverb::test::expectInputError([&] { computeImageSources(scene, source, listener, model, options); },
                                      {"use order 3 or less"});
}

TEST(ImageSources, SpecularShareAndAirAreApplied) {
  const Eigen::Vector3d size(5, 4, 3);
  const AcousticScene scene(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(0.1, 0.36));
  AirConditions air;  // 20 C, 50 %
  const PropagationModel model = PropagationModel::from(air, {});
  const auto paths = computeImageSources(scene, {1, 1, 1}, {3, 2.5, 1.5}, model, {1, true});
  for (const auto& path : paths) {
    for (int b = 0; b < kOctaveBandCount; ++b) {
      const double expected = std::pow(std::sqrt(0.9 * 0.64), path.order) / path.distance_m *
                              std::exp(-0.5 * model.air_attenuation_per_m[b] * path.distance_m);
      EXPECT_NEAR(path.pressure_gain[b] / expected, 1.0, 1e-9);
    }
  }
}

TEST(ImageSources, AnObstacleBlocksTheDirectSound) {
  auto mesh = room_reverb::test::shoeboxMesh({6, 4, 3});
  // A free-standing panel (two triangles) across the line of sight at x = 3.
  const int base = static_cast<int>(mesh.vertices.size());
  for (const auto& v : {Eigen::Vector3d(3, 1, 0.5), Eigen::Vector3d(3, 3, 0.5), Eigen::Vector3d(3, 3, 2.5), Eigen::Vector3d(3, 1, 2.5)}) mesh.vertices.push_back(v);
  mesh.triangles.push_back({base, base + 1, base + 2});
  mesh.triangles.push_back({base, base + 2, base + 3});
  mesh.triangle_material.push_back(0);
  mesh.triangle_material.push_back(0);
  const AcousticScene scene(mesh, room_reverb::test::uniformLibrary(0.2, 0.0), {}, false);
  const PropagationModel model = PropagationModel::from(AirConditions{}, {});
  const auto paths = computeImageSources(scene, {1, 2, 1.5}, {5, 2, 1.5}, model, {1, true});
  for (const auto& path : paths) EXPECT_NE(path.order, 0);
  EXPECT_FALSE(paths.empty());  // floor and ceiling reflections pass under and over it
}

TEST(ImageSources, RenderedTapSitsAtTheFractionalDelay) {
  // One path of 40.1234 ms (later than the tap's 21 ms half-length, so none of the
  // zero-phase tap is cut off at t = 0): its group delay is the path's delay.
  SpecularPath path;
  path.delay_s = 0.0401234;
  path.pressure_gain.fill(0.5);
  path.arrival_direction = Eigen::Vector3d::UnitX();
  SynthesisOptions options;
  options.duration_s = 0.2;
  options.ambisonic_order = 1;
  const AudioBuffer ir = synthesizeImpulseResponse({path}, nullptr, options);
  double e = 0.0;
  for (float v : ir.channels[0]) e += static_cast<double>(v) * v;
  // Delay from the phase slope of the tap's spectrum (group delay) at 0.5, 1, 4 and 10 kHz.
  RealFft fft(ir.frameCount());
  const auto spectrum = fft.forward(ir.channels[0]);
  const double bin_hz = 48000.0 / ir.frameCount();
  for (double f : {500.0, 1000.0, 4000.0, 10000.0}) {
    const auto k = static_cast<std::size_t>(f / bin_hz);
    const double phase_step = std::arg(spectrum[k + 1] * std::conj(spectrum[k]));
    const double delay_samples = -phase_step / (2 * M_PI * bin_hz) * 48000.0;
    EXPECT_NEAR(delay_samples, path.delay_s * 48000.0, 0.1) << f << " Hz";
  }
  // Flat gain 0.5 over the bank's 37 Hz - 22 kHz: energy 0.25 less the 6-7 % above and below.
  EXPECT_NEAR(e, 0.25 * 0.935, 0.25 * 0.03);
  // First-order harmonics of +x: X (ACN 3) equals W, Y and Z vanish.
  EXPECT_NEAR(ir.channels[3][1926], ir.channels[0][1926], 1e-6);
  EXPECT_NEAR(ir.channels[1][1926], 0.0, 1e-6);
}

TEST(ImageSources, EveryPathsPolylineGoesThroughItsReflectionPoints) {
  // Each computed path, drawn: from the source through one point per reflection to the
  // listener, its length the path's unfolded distance, each point on the box's face of the
  // plane it reflects in; a path is not drawn for a listener it does not reach.
  const Eigen::Vector3d size(6.2, 4.3, 2.9);
  const Eigen::Vector3d source(1.7, 1.1, 1.3), listener(4.4, 3.05, 1.6);
  const AcousticScene scene(room_reverb::test::shoeboxMesh(size), room_reverb::test::uniformLibrary(0.2, 0.0));
  const auto paths = computeImageSources(scene, source, listener, PropagationModel());
  ASSERT_EQ(paths.size(), 63u);
  for (const SpecularPath& path : paths) {
    const auto points = specularPathPoints(scene, source, listener, path);
    ASSERT_TRUE(points.has_value()) << "order " << path.order;
    ASSERT_EQ(points->size(), static_cast<std::size_t>(path.order) + 2);
    EXPECT_LT((points->front() - source).norm(), 1e-12);
    EXPECT_LT((points->back() - listener).norm(), 1e-12);
    double length = 0.0;
    for (std::size_t i = 1; i < points->size(); ++i) length += ((*points)[i] - (*points)[i - 1]).norm();
    EXPECT_NEAR(length, path.distance_m, 1e-9);
    for (std::size_t k = 0; k < path.triangles.size(); ++k) {
      const ScenePlane& plane = scene.planes()[scene.planeOf(path.triangles[k])];
      EXPECT_NEAR(plane.normal.dot((*points)[k + 1]) - plane.offset, 0.0, 1e-9);
    }
  }
  // The floor's first-order path does not reach a listener below the floor (the wrong
  // side of its plane), and a triangle the scene does not have gives no path.
  const auto floor = std::find_if(paths.begin(), paths.end(), [&](const SpecularPath& p) {
    return p.order == 1 && std::abs(p.image_position.z() + source.z()) < 1e-9;
  });
  ASSERT_NE(floor, paths.end());
  EXPECT_FALSE(specularPathPoints(scene, source, Eigen::Vector3d(4.4, 3.05, -0.5), *floor).has_value());
  SpecularPath unknown = *floor;
  unknown.triangles = {scene.mesh().triangleCount()};
  EXPECT_FALSE(specularPathPoints(scene, source, listener, unknown).has_value());
}

TEST(EdgeDiffraction, KurzeAndersonLossIsContinuousThroughTheShadowBoundary) {
  EXPECT_NEAR(barrierLossDb(0.0), 5.0, 1e-9);
  EXPECT_NEAR(barrierLossDb(1e-9), 5.0, 1e-3);
  EXPECT_NEAR(barrierLossDb(-1e-9), 5.0, 1e-3);
  // N = 1: 5 + 20 log10(sqrt(2 pi) / tanh sqrt(2 pi)) = 13.1 dB (Maekawa's chart: 13 dB).
  EXPECT_NEAR(barrierLossDb(1.0), 5.0 + 20.0 * std::log10(std::sqrt(2.0 * M_PI) / std::tanh(std::sqrt(2.0 * M_PI))), 1e-9);
  EXPECT_NEAR(barrierLossDb(1.0), 13.1, 0.05);
  EXPECT_EQ(barrierLossDb(100.0), 20.0);  // one edge takes at most 20 dB
  EXPECT_GT(barrierLossDb(-0.05), 0.0);
  EXPECT_LT(barrierLossDb(-0.05), 5.0);
  EXPECT_EQ(barrierLossDb(-0.3), 0.0);
  // Monotone from the lit side into the shadow.
  double last = 0.0;
  for (double n = -0.25; n < 3.0; n += 0.001) {
    EXPECT_GE(barrierLossDb(n) + 1e-9, last) << n;
    last = barrierLossDb(n);
  }
}

TEST(EdgeDiffraction, TheDetourGoesOverTheNearestEdgeOrAcrossTheTop) {
  CuboidObject screen;  // a thin screen 2 m wide, 1 m high, standing on the floor at x = 3
  screen.center_m = {3.0, 2.0, 0.5};
  screen.size_m = {0.02, 2.0, 1.0};
  const Eigen::Vector3d source(1.0, 2.0, 0.6), listener(5.0, 2.0, 0.6);
  const auto over = shortestEdgeDetour(screen, source, listener);
  ASSERT_TRUE(over.has_value());
  EXPECT_TRUE(over->shadowed);
  // Over the top edge: up 0.4 m over 2 m each way (the screen's 1 cm half-thickness aside).
  const double expected = 2.0 * std::hypot(2.0 - 0.01, 0.4) + 0.02;
  EXPECT_NEAR(over->length_m, expected, 1e-4);
  EXPECT_NEAR(over->path_difference_m, expected - 4.0, 1e-4);
  ASSERT_FALSE(over->turns.empty());
  for (const Eigen::Vector3d& turn : over->turns) EXPECT_NEAR(turn.z(), 1.0, 1e-6);
  // A thick cabinet: across its top, over two edges.
  CuboidObject cabinet = screen;
  cabinet.size_m = {1.0, 2.0, 1.0};
  const auto across = shortestEdgeDetour(cabinet, source, listener);
  ASSERT_TRUE(across.has_value());
  EXPECT_NEAR(across->length_m, 2.0 * std::hypot(1.5, 0.4) + 1.0, 1e-4);
  // In view, above the screen: not shadowed, the path difference small.
  const auto lit = shortestEdgeDetour(screen, Eigen::Vector3d(1.0, 2.0, 1.1), Eigen::Vector3d(5.0, 2.0, 1.1));
  ASSERT_TRUE(lit.has_value());
  EXPECT_FALSE(lit->shadowed);
  EXPECT_LT(lit->path_difference_m, 0.01);
  EXPECT_FALSE(shortestEdgeDetour(screen, Eigen::Vector3d(3.0, 2.0, 0.5), listener).has_value());  // inside it
}

TEST(EdgeDiffraction, TheDetourIsTheShortestWayOverOneEdgeOrTwo) {
  // A turned box and source-listener pairs around it, lit and shadowed: the detour's
  // length against a search of every way over one edge (2001 points along it) and over
  // two parallel edges (201 x 201), each leg clear of the box.
  CuboidObject box;
  box.center_m = {0.0, 0.0, 0.5};
  box.size_m = {1.2, 0.7, 1.0};
  box.yaw_rad = 0.5;
  const Eigen::Vector3d half = 0.5 * box.size_m;
  // The twelve edges: pairs of the eight corners that differ in one coordinate's sign.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> edges;  // room frame
  for (int i = 0; i < 8; ++i) {
    for (int j = i + 1; j < 8; ++j) {
      if (__builtin_popcount(i ^ j) != 1) continue;
      const auto corner = [&](int bits) {
        return Eigen::Vector3d((bits & 1 ? 1 : -1) * half.x(), (bits & 2 ? 1 : -1) * half.y(),
                               (bits & 4 ? 1 : -1) * half.z());
      };
      edges.emplace_back(fromCuboidFrame(box, corner(i)), fromCuboidFrame(box, corner(j)));
    }
  }
  ASSERT_EQ(edges.size(), 12u);
  const auto clear = [&](const std::vector<Eigen::Vector3d>& way) {
    for (std::size_t k = 0; k + 1 < way.size(); ++k) {
      if (segmentCrossesCuboid(box, way[k], way[k + 1])) return false;
    }
    return true;
  };
  const auto length = [](const std::vector<Eigen::Vector3d>& way) {
    double total = 0.0;
    for (std::size_t k = 0; k + 1 < way.size(); ++k) total += (way[k + 1] - way[k]).norm();
    return total;
  };
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), height(0.05, 1.6), radius(0.9, 2.5);
  std::size_t shadowed = 0, over_two = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const auto around = [&] {
      const double a = angle(rng), r = radius(rng);
      return Eigen::Vector3d(r * std::cos(a), r * std::sin(a), height(rng));
    };
    const Eigen::Vector3d s = around(), l = around();
    const auto detour = shortestEdgeDetour(box, s, l);
    ASSERT_TRUE(detour.has_value()) << trial;
    double best = std::numeric_limits<double>::infinity();
    bool best_over_two = false;
    for (const auto& [from, to] : edges) {
      for (int i = 0; i <= 2000; ++i) {
        const std::vector<Eigen::Vector3d> way = {s, from + (to - from) * (i / 2000.0), l};
        if (length(way) < best && clear(way)) best = length(way), best_over_two = false;
      }
    }
    for (const auto& a : edges) {
      for (const auto& b : edges) {
        const Eigen::Vector3d da = a.second - a.first, db = b.second - b.first, offset = b.first - a.first;
        if (&a == &b || da.cross(db).norm() > 1e-9 || std::abs(offset.dot(da.normalized())) > 1e-9) continue;
        for (int i = 0; i <= 200; ++i) {
          for (int j = 0; j <= 200; ++j) {
            const std::vector<Eigen::Vector3d> way = {s, a.first + da * (i / 200.0), b.first + db * (j / 200.0), l};
            if (length(way) < best && clear(way)) best = length(way), best_over_two = true;
          }
        }
      }
    }
    // The grids' points are on the edges, so the search is never shorter than the truth.
    EXPECT_LT(detour->length_m, best + 1e-6) << trial;
    EXPECT_GT(detour->length_m, best - 2e-3) << trial;
    shadowed += detour->shadowed ? 1 : 0;
    over_two += best_over_two ? 1 : 0;
  }
  EXPECT_GE(shadowed, 4u) << "the trials should include shadowed pairs";
  EXPECT_GE(over_two, 1u) << "the trials should include a way across a face";
}

TEST(ImageSources, TheDirectSoundBendsAroundAnObjectAndFadesIntoItsShadow) {
  // A 6 x 4 x 3 m room model with a 1.2 m high screen between source and listener: the
  // direct sound arrives over its top edge, later and weaker in the higher bands; raising
  // the listener through the shadow's edge, the direct sound's level changes smoothly.
  RoomModel model = room_reverb::test::plasterRoom({6.0, 4.0, 3.0});
  model.objects.push_back(room_reverb::test::woodCuboid("screen", {3.0, 2.0, 0.6}, {0.02, 3.0, 1.2}));
  const AcousticScene scene = roomModelToScene(model, MaterialLibrary::loadDefault());
  AirConditions no_air;
  no_air.enabled = false;
  const PropagationModel propagation = PropagationModel::from(no_air, {});
  const Eigen::Vector3d source(1.0, 2.0, 0.6);
  const auto direct = [&](double height) {
    ImageSourceOptions options;
    options.max_order = 0;
    const auto paths = computeImageSources(scene, source, {5.0, 2.0, height}, propagation, options);
    return paths.empty() ? std::optional<SpecularPath>() : std::optional<SpecularPath>(paths.front());
  };
  const auto behind = direct(0.6);
  ASSERT_TRUE(behind.has_value()) << "the direct sound is heard behind the screen";
  const double detour = 2.0 * std::hypot(2.0 - 0.01, 0.6) + 0.02;
  EXPECT_NEAR(behind->distance_m, detour, 1e-4);
  EXPECT_NEAR(behind->delay_s, detour / propagation.speed_of_sound_m_s, 1e-9);
  EXPECT_LT(behind->pressure_gain[7], behind->pressure_gain[2]);  // 8 kHz below 250 Hz
  const double n_1k = 2.0 * (detour - 4.0) * 1000.0 / propagation.speed_of_sound_m_s;
  EXPECT_NEAR(20.0 * std::log10(behind->pressure_gain[4] * detour), -barrierLossDb(n_1k), 1e-6);
  ImageSourceOptions plain;
  plain.max_order = 0;
  plain.diffract_direct_sound = false;
  EXPECT_TRUE(computeImageSources(scene, source, {5.0, 2.0, 0.6}, propagation, plain).empty());
  // Through the shadow's edge (the line of sight grazes the top at z = 1.2 m for a listener
  // at 1.8 m): no step larger than the slope around it.
  double last_db = 0.0, largest_step = 0.0;
  for (double z = 1.6; z <= 2.0; z += 0.002) {
    const auto path = direct(z);
    ASSERT_TRUE(path.has_value()) << z;
    const double db = 20.0 * std::log10(path->pressure_gain[4] * (Eigen::Vector3d(5.0, 2.0, z) - source).norm());
    if (z > 1.6) largest_step = std::max(largest_step, std::abs(db - last_db));
    last_db = db;
  }
  EXPECT_LT(largest_step, 0.5);
  // 0.2 m above the shadow's edge the screen is still inside the first Fresnel zone at
  // 1 kHz (about 0.6 m across here), and takes less than at grazing; at 16 kHz it is clear.
  EXPECT_GT(last_db, -5.0);
  EXPECT_LT(last_db, -0.5);
  const auto clear = direct(2.0);
  ASSERT_TRUE(clear.has_value());
  EXPECT_NEAR(clear->pressure_gain[8] * (Eigen::Vector3d(5.0, 2.0, 2.0) - source).norm(), 1.0, 1e-9);
}
