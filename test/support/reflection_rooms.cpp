#include "reflection_rooms.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <stdexcept>

#include "room_reverb/ambisonics/bformat.h"

namespace room_reverb::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFs = 48000.0;
constexpr double kSpeedOfSound = 343.0;
constexpr double kDurationS = 0.4;
constexpr int kMaxOrder = 3;
// The pulse: a sinc low-passed at 20 kHz under a Blackman window of +-32 samples, so the
// rendered arrival is band-limited and lands at a fractional sample exactly.
constexpr double kPulseCutoffHz = 20000.0;
constexpr int kPulseHalfLength = 32;
// The diffuse tail: its energy per millisecond of W is kDiffuseAt30MsDb below the direct
// sound's energy 30 ms after the direct sound, growing as the square of the time since the
// direct sound before that (the density of image sources grows as t^2) and decaying with
// the room's Sabine T60 after.
constexpr double kDiffuseAt30MsDb = -25.0;
constexpr double kDiffuseReferenceS = 0.030;

enum class Kind { kShoebox, kDull, kClosePair, kNearDirect, kLong, kTall, kReflector };

struct Recipe {
  Kind kind;
  std::uint32_t seed;
  double min_reflection = 0.75, max_reflection = 0.85;  // wall pressure reflection factors
  double dull_cutoff_hz = 0.0;                          // 0: walls reflect every frequency alike
  double snr_db = 60.0;                                 // W's peak over the noise floor's RMS
};

// A reflector panel parallel to the x walls at x = x_m, spanning [y0, y1] x [z0, z1].
struct Panel {
  double x_m, y0, y1, z0, z1, reflection;
};

struct Geometry {
  Eigen::Vector3d size, source, receiver;
  std::array<double, 6> reflection{};  // walls x = 0, x = Lx, y = 0, y = Ly, z = 0, z = Lz
  std::optional<Panel> panel;
};

struct ImageSource {
  int order;
  Eigen::Vector3d position;
  double gain;  // product of the reflection factors
};

const std::vector<Recipe>& recipes(ReflectionRoomSet set) {
  static const std::vector<Recipe> development = [] {
    std::vector<Recipe> r;
    for (std::uint32_t s = 1; s <= 8; ++s) r.push_back({Kind::kShoebox, s});
    for (std::uint32_t s = 11; s <= 13; ++s) r.push_back({Kind::kDull, s, 0.75, 0.85, 2500.0, 45.0});
    for (std::uint32_t s = 21; s <= 23; ++s) r.push_back({Kind::kClosePair, s});
    for (std::uint32_t s = 31; s <= 33; ++s) r.push_back({Kind::kNearDirect, s});
    return r;
  }();
  static const std::vector<Recipe> held_out = [] {
    std::vector<Recipe> r;
    for (std::uint32_t s = 101; s <= 106; ++s) r.push_back({Kind::kShoebox, s, 0.7, 0.9});
    for (std::uint32_t s = 111; s <= 112; ++s) r.push_back({Kind::kLong, s});
    r.push_back({Kind::kTall, 113, 0.8, 0.9});
    for (std::uint32_t s = 121; s <= 123; ++s) r.push_back({Kind::kReflector, s});
    for (std::uint32_t s = 131; s <= 133; ++s) r.push_back({Kind::kDull, s, 0.8, 0.9, 2000.0, 45.0});
    for (std::uint32_t s = 141; s <= 142; ++s) r.push_back({Kind::kClosePair, s, 0.7, 0.85});
    for (std::uint32_t s = 151; s <= 152; ++s) r.push_back({Kind::kNearDirect, s, 0.8, 0.9});
    return r;
  }();
  return set == ReflectionRoomSet::kDevelopment ? development : held_out;
}

const char* kindName(Kind kind) {
  switch (kind) {
    case Kind::kShoebox: return "shoebox";
    case Kind::kDull: return "dull";
    case Kind::kClosePair: return "close-pair";
    case Kind::kNearDirect: return "near-direct";
    case Kind::kLong: return "long";
    case Kind::kTall: return "tall";
    case Kind::kReflector: return "reflector";
  }
  return "?";
}

// Allen & Berkley's images of a shoebox: along each axis the image coordinate is
// (1 - 2p) s + 2 m L, with |m - p| reflections on the wall at 0 and |m| on the wall at L.
std::vector<ImageSource> shoeboxImages(const Geometry& g) {
  std::vector<ImageSource> out;
  for (int mx = -2; mx <= 2; ++mx)
    for (int px = 0; px <= 1; ++px)
      for (int my = -2; my <= 2; ++my)
        for (int py = 0; py <= 1; ++py)
          for (int mz = -2; mz <= 2; ++mz)
            for (int pz = 0; pz <= 1; ++pz) {
              const std::array<int, 3> m{mx, my, mz}, p{px, py, pz};
              int order = 0;
              double gain = 1.0;
              Eigen::Vector3d position;
              for (int a = 0; a < 3; ++a) {
                const int low = std::abs(m[a] - p[a]), high = std::abs(m[a]);
                order += low + high;
                gain *= std::pow(g.reflection[2 * a], low) * std::pow(g.reflection[2 * a + 1], high);
                position[a] = (1 - 2 * p[a]) * g.source[a] + 2 * m[a] * g.size[a];
              }
              if (order <= kMaxOrder) out.push_back({order, position, gain});
            }
  if (g.panel) {
    // The panel's own first-order image, where the specular point lies on the panel (the
    // source and the receiver are on the same side of it).
    const Panel& panel = *g.panel;
    const Eigen::Vector3d image(2.0 * panel.x_m - g.source.x(), g.source.y(), g.source.z());
    const double t = (panel.x_m - g.receiver.x()) / (image.x() - g.receiver.x());
    const Eigen::Vector3d hit = g.receiver + t * (image - g.receiver);
    if (hit.y() >= panel.y0 && hit.y() <= panel.y1 && hit.z() >= panel.z0 && hit.z() <= panel.z1) {
      out.push_back({1, image, panel.reflection});
    }
  }
  return out;
}

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

Eigen::Vector3d randomPoint(std::mt19937& rng, const Eigen::Vector3d& size) {
  return {uniform(rng, 0.6, size.x() - 0.6), uniform(rng, 0.6, size.y() - 0.6), uniform(rng, 1.0, std::min(2.0, size.z() - 0.5))};
}

Geometry drawGeometry(const Recipe& recipe, std::mt19937& rng) {
  Geometry g;
  switch (recipe.kind) {
    case Kind::kLong: g.size = {uniform(rng, 8.0, 9.1), uniform(rng, 2.2, 2.8), uniform(rng, 2.3, 2.6)}; break;
    case Kind::kTall: g.size = {uniform(rng, 4.9, 5.5), uniform(rng, 4.2, 4.8), uniform(rng, 5.5, 6.5)}; break;
    default: g.size = {uniform(rng, 4.9, 9.1), uniform(rng, 3.2, 6.5), uniform(rng, 2.5, 3.5)};
  }
  for (double& r : g.reflection) r = uniform(rng, recipe.min_reflection, recipe.max_reflection);
  if (recipe.kind == Kind::kNearDirect) {
    // Source and receiver both close to one side wall, a few metres apart: the wall's
    // reflection follows the direct sound within a few milliseconds.
    const double wall_distance_s = uniform(rng, 0.3, 0.8), wall_distance_r = uniform(rng, 0.3, 0.8);
    const double xs = uniform(rng, 0.8, 2.0), xr = std::min(g.size.x() - 0.6, xs + uniform(rng, 2.0, 4.0));
    g.source = {xs, wall_distance_s, uniform(rng, 1.0, 2.0)};
    g.receiver = {xr, wall_distance_r, uniform(rng, 1.0, 2.0)};
  } else {
    do {
      g.source = randomPoint(rng, g.size);
      g.receiver = randomPoint(rng, g.size);
    } while ((g.source - g.receiver).norm() < 1.2);
  }
  if (recipe.kind == Kind::kReflector) {
    // A 1.2 x 1.0 m panel between the source and the x = Lx wall, 0.6-1.2 m beyond the
    // further of the two, lit from the source's side.
    const double x = std::max(g.source.x(), g.receiver.x()) + uniform(rng, 0.6, 1.2);
    const double yc = 0.5 * (g.source.y() + g.receiver.y()) + uniform(rng, -0.3, 0.3);
    const double zc = 0.5 * (g.source.z() + g.receiver.z()) + uniform(rng, -0.2, 0.2);
    if (x < g.size.x() - 0.2) g.panel = Panel{x, yc - 0.6, yc + 0.6, zc - 0.5, zc + 0.5, uniform(rng, 0.8, 0.9)};
  }
  return g;
}

void addPulse(core::AudioBuffer& ambix, const ArrivalPulse& pulse, const Eigen::Vector3d& u) {
  // SN3D first order: a plane wave from u gives W = p, (X, Y, Z) = u p.
  const std::array<double, 4> gains{1.0, u.y(), u.z(), u.x()};
  for (std::size_t i = 0; i < pulse.samples.size(); ++i) {
    const long n = pulse.first + static_cast<long>(i);
    if (n < 0 || n >= static_cast<long>(ambix.frameCount())) continue;
    for (std::size_t c = 0; c < 4; ++c) ambix.channels[c][static_cast<std::size_t>(n)] += static_cast<float>(gains[c] * pulse.samples[i]);
  }
}

double sabineT60(const Geometry& g) {
  const double volume = g.size.prod();
  const std::array<double, 3> area{g.size.y() * g.size.z(), g.size.x() * g.size.z(), g.size.x() * g.size.y()};
  double absorption_area = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) absorption_area += area[a] * (1.0 - std::pow(g.reflection[2 * a + side], 2));
  return 0.161 * volume / absorption_area;
}

// Diffuse field: independent Gaussian noise in each channel (W variance s^2, X, Y, Z
// s^2 / 3 each: an isotropic field in SN3D), low-passed thrice where the walls are dull.
// Its level and decay belong to the room, not to the receiver: they are set by the direct
// sound at the room's own receiver (`room_direct_time_s`, `room_direct_energy`), and a
// moved receiver hears the same energy at the same time after the emission. Only its rise
// starts at the receiver's own direct sound (`direct_time_s`), nothing arriving before it.
void addDiffuseTail(core::AudioBuffer& ambix, const Geometry& g, const Recipe& recipe, double direct_time_s,
                    double room_direct_time_s, double room_direct_energy, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const double per_ms = room_direct_energy * std::pow(10.0, kDiffuseAt30MsDb / 10.0);
  const double variance_at_reference = per_ms / (0.001 * kFs);
  const double decay_per_s = 6.0 * std::log(10.0) / sabineT60(g);  // energy
  const std::size_t frames = ambix.frameCount();
  const double a = recipe.dull_cutoff_hz > 0.0 ? std::exp(-2.0 * kPi * recipe.dull_cutoff_hz / kFs) : 0.0;
  const int passes = recipe.dull_cutoff_hz > 0.0 ? 3 : 0;
  for (std::size_t c = 0; c < 4; ++c) {
    std::vector<double> noise(frames);
    for (double& v : noise) v = normal(rng);
    for (int p = 0; p < passes; ++p) {
      double y = 0.0;
      for (double& v : noise) v = y = (1.0 - a) * v + a * y;
    }
    double power = 0.0;
    for (double v : noise) power += v * v;
    const double scale = 1.0 / std::sqrt(power / static_cast<double>(frames)) / (c == 0 ? 1.0 : std::sqrt(3.0));
    for (std::size_t n = 0; n < frames; ++n) {
      const double t = static_cast<double>(n) / kFs;
      const double tau = t - direct_time_s;
      if (tau <= 0.0) continue;
      const double variance = variance_at_reference * std::pow(tau / kDiffuseReferenceS, 2) *
                              std::exp(-decay_per_s * (t - room_direct_time_s - kDiffuseReferenceS));
      ambix.channels[c][n] += static_cast<float>(scale * noise[n] * std::sqrt(variance));
    }
  }
}

// The arrivals of a geometry with their levels, without rendering the room.
std::vector<ImageArrival> arrivals(const Geometry& g, const Recipe& recipe) {
  std::vector<ImageArrival> out;
  for (const ImageSource& image : shoeboxImages(g)) {
    const Eigen::Vector3d path = image.position - g.receiver;
    const double distance = path.norm();
    ImageArrival a;
    a.order = image.order;
    a.time_s = distance / kSpeedOfSound;
    a.direction = path / distance;
    const ArrivalPulse pulse = renderArrivalPulse(a.time_s * kFs, image.gain / distance, recipe.dull_cutoff_hz > 0.0 ? image.order : 0,
                                    recipe.dull_cutoff_hz);
    double e = 0.0;
    for (double v : pulse.samples) e += v * v;
    a.level = std::sqrt(e);
    out.push_back(a);
  }
  std::sort(out.begin(), out.end(), [](const ImageArrival& x, const ImageArrival& y) { return x.time_s < y.time_s; });
  return out;
}

// The reflections the scoring asks for (reflection_score.h), restated here so that the
// close-pair and near-direct rooms can be drawn until they hold one of their kind.
bool audible(const ImageArrival& a, const ImageArrival& direct) {
  return a.order >= 1 && a.order <= 2 && a.time_s - direct.time_s <= 0.030 && a.level >= direct.level * std::pow(10.0, -14.0 / 20.0);
}

bool holdsItsKind(const std::vector<ImageArrival>& images, Kind kind) {
  const ImageArrival& direct = images.front();
  for (std::size_t i = 0; i < images.size(); ++i) {
    if (!audible(images[i], direct)) continue;
    if (kind == Kind::kNearDirect && images[i].time_s - direct.time_s >= 0.0005 && images[i].time_s - direct.time_s <= 0.0032)
      return true;
    if (kind == Kind::kClosePair) {
      for (std::size_t j = i + 1; j < images.size(); ++j) {
        const double gap = images[j].time_s - images[i].time_s;
        if (gap >= 0.0005 && gap <= 0.0007 && audible(images[j], direct)) return true;
      }
    }
  }
  return false;
}

}  // namespace

ArrivalPulse renderArrivalPulse(double delay_samples, double amplitude, int bounces, double cutoff_hz) {
  ArrivalPulse pulse;
  const long centre = static_cast<long>(std::floor(delay_samples));
  pulse.first = centre - kPulseHalfLength;
  const double fc = kPulseCutoffHz / kFs;
  const int tail = bounces > 0 && cutoff_hz > 0.0 ? 600 : 0;
  pulse.samples.assign(2 * kPulseHalfLength + 2 + tail, 0.0);
  for (std::size_t i = 0; i < 2 * kPulseHalfLength + 2; ++i) {
    const double t = static_cast<double>(pulse.first + static_cast<long>(i)) - delay_samples;
    if (std::abs(t) > kPulseHalfLength) continue;
    const double x = 2.0 * fc * t;
    const double sinc = std::abs(x) < 1e-12 ? 1.0 : std::sin(kPi * x) / (kPi * x);
    const double u = (t + kPulseHalfLength) / (2.0 * kPulseHalfLength);
    const double blackman = 0.42 - 0.5 * std::cos(2.0 * kPi * u) + 0.08 * std::cos(4.0 * kPi * u);
    pulse.samples[i] = amplitude * 2.0 * fc * sinc * blackman;
  }
  if (tail > 0) {
    const double a = std::exp(-2.0 * kPi * cutoff_hz / kFs);
    for (int b = 0; b < bounces; ++b) {
      double y = 0.0;
      for (double& v : pulse.samples) v = y = (1.0 - a) * v + a * y;
    }
  }
  return pulse;
}


core::RoomModel roomModelOf(const ReflectionRoomGeometry& g) {
  core::RoomModel model;
  model.size_m = g.size_m;
  for (const char* name : core::kRoomSurfaceNames) model.surfaces[name] = core::SurfaceAssignment{"plaster_smooth", 1.0};
  model.rig_position_m = g.receiver_m;
  if (g.panel) {
    core::CuboidObject panel;
    panel.label = "reflector panel";
    panel.material = "plywood_panel";
    panel.size_m = {0.02, g.panel->y1 - g.panel->y0, g.panel->z1 - g.panel->z0};
    panel.center_m = {g.panel->x_m + 0.01, 0.5 * (g.panel->y0 + g.panel->y1), 0.5 * (g.panel->z0 + g.panel->z1)};
    model.objects.push_back(panel);
  }
  return model;
}

std::size_t reflectionRoomCount(ReflectionRoomSet set) { return recipes(set).size(); }

ReflectionRoom reflectionRoom(ReflectionRoomSet set, std::size_t index) {
  return reflectionRoom(set, index, Eigen::Vector3d::Zero());
}

ReflectionRoom reflectionRoom(ReflectionRoomSet set, std::size_t index, const Eigen::Vector3d& receiver_offset_m) {
  const Recipe& recipe = recipes(set).at(index);
  std::mt19937 rng(recipe.seed);
  Geometry g = drawGeometry(recipe, rng);
  std::vector<ImageArrival> images = arrivals(g, recipe);
  if (recipe.kind == Kind::kClosePair || recipe.kind == Kind::kNearDirect) {
    for (int attempt = 0; attempt < 2000 && !holdsItsKind(images, recipe.kind); ++attempt) {
      g = drawGeometry(recipe, rng);
      images = arrivals(g, recipe);
    }
  }

  const ImageArrival room_direct = images.front();  // at the room's own receiver
  if (!receiver_offset_m.isZero()) {
    g.receiver += receiver_offset_m;
    const Eigen::Vector3d clearance = (g.receiver.array().min((g.size - g.receiver).array())).matrix();
    if (clearance.minCoeff() < 0.3 || (g.receiver - g.source).norm() < 0.5 ||
        (g.panel && g.receiver.x() > g.panel->x_m - 0.1)) {
      throw std::invalid_argument("reflectionRoom: the moved receiver is too close to a wall, the source or the panel");
    }
    images = arrivals(g, recipe);
  }

  ReflectionRoom room;
  room.name = std::string(kindName(recipe.kind)) + " " + std::to_string(recipe.seed);
  room.geometry.size_m = g.size;
  room.geometry.source_m = g.source;
  room.geometry.receiver_m = g.receiver;
  if (g.panel) room.geometry.panel = ReflectorPanel{g.panel->x_m, g.panel->y0, g.panel->y1, g.panel->z0, g.panel->z1};
  room.ambix = core::makeSilentBuffer(4, static_cast<std::size_t>(kDurationS * kFs), kFs);
  for (const ImageSource& image : shoeboxImages(g)) {
    const Eigen::Vector3d path = image.position - g.receiver;
    const double distance = path.norm();
    addPulse(room.ambix,
             renderArrivalPulse(distance / kSpeedOfSound * kFs, image.gain / distance,
                         recipe.dull_cutoff_hz > 0.0 ? image.order : 0, recipe.dull_cutoff_hz),
             path / distance);
  }
  const ImageArrival& direct = images.front();
  addDiffuseTail(room.ambix, g, recipe, direct.time_s, room_direct.time_s, room_direct.level * room_direct.level, rng);
  room.noiseless = room.ambix;
  float peak = 0.0f;
  for (float v : room.ambix.channels[0]) peak = std::max(peak, std::abs(v));
  const double floor = peak * std::pow(10.0, -recipe.snr_db / 20.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (auto& channel : room.ambix.channels)
    for (float& v : channel) v += static_cast<float>(floor * normal(rng));
  room.images = std::move(images);
  return room;
}

}  // namespace room_reverb::test
