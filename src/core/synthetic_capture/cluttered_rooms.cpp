#include "room_reverb/synthetic_capture/cluttered_rooms.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>

namespace room_reverb::core {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Ranges {
  double x_lo, x_hi, y_lo, y_hi, z_lo, z_hi;  // main-wall box
  double recess_lo, recess_hi;                // recess depth [m]
  int max_recesses;
  double p_kitchen, p_shelving, p_wardrobe, p_sofa, p_table, p_radiator;
  int clutter_per_shelf;
};

Ranges rangesOf(ClutterSet set) {
  if (set == ClutterSet::kDevelopment) {
    return {4.0, 8.0, 3.0, 5.5, 2.3, 3.0, 0.08, 0.20, 1, 0.5, 0.5, 0.4, 0.4, 0.6, 0.5, 6};
  }
  return {5.0, 11.0, 2.6, 7.0, 2.4, 3.6, 0.10, 0.30, 2, 0.6, 0.6, 0.5, 0.5, 0.7, 0.6, 9};
}

std::uint32_t seedOf(ClutterSet set, int index) {
  const auto i = static_cast<std::uint32_t>(index);
  switch (set) {
    case ClutterSet::kDevelopment: return 1000u + i;
    case ClutterSet::kHeldOut: return 777000u + i;
    case ClutterSet::kDevelopmentLarge: return 4242000u + i;
  }
  return 0u;
}

class RoomBuilder {
 public:
  RoomBuilder(ClutterSet set, int index)
      : ranges_(rangesOf(set)), rng_(seedOf(set, index)) {}

  ClutteredRoom build(const std::string& name) {
    ClutteredRoom room;
    room.name = name;
    size_ = {uniform(ranges_.x_lo, ranges_.x_hi), uniform(ranges_.y_lo, ranges_.y_hi), uniform(ranges_.z_lo, ranges_.z_hi)};
    rig_ = {uniform(0.9, size_.x() - 0.9), uniform(0.9, size_.y() - 0.9), uniform(1.2, 1.7)};
    const double rig_yaw = uniform(-kPi / 4, kPi / 4);
    const char* floors[] = {"parquet_on_concrete", "linoleum_on_concrete", "carpet_on_concrete", "tiles_ceramic"};
    const char* ceilings[] = {"plaster_smooth", "acoustic_ceiling_tiles"};
    surfaces_["floor"] = {floors[std::uniform_int_distribution<int>(0, 3)(rng_)], 1.0};
    surfaces_["ceiling"] = {ceilings[std::uniform_int_distribution<int>(0, 1)(rng_)], 1.0};
    for (int f = 2; f < 6; ++f) surfaces_[kRoomSurfaceNames[static_cast<std::size_t>(f)]] = {"plaster_smooth", 1.0};

    // Recesses: on walls of different axes, so that the wall pieces of one span the other.
    std::vector<int> walls = {2, 3, 4, 5};
    std::shuffle(walls.begin(), walls.end(), rng_);
    const int recesses = std::uniform_int_distribution<int>(1, ranges_.max_recesses)(rng_);
    for (int f : walls) {
      if (static_cast<int>(room.recessed_walls.size()) >= recesses) break;
      const bool same_axis = std::any_of(room.recessed_walls.begin(), room.recessed_walls.end(),
                                         [&](int g) { return (g - 2) / 2 == (f - 2) / 2; });
      if (!same_axis) room.recessed_walls.push_back(f), recess_depth_[f - 2] = uniform(ranges_.recess_lo, ranges_.recess_hi);
    }

    for (int f : room.recessed_walls) addRecess(f, chance(0.5));
    for (int f = 2; f < 6; ++f) addFixture(labelled(skirting(f), "skirting"));
    // Furniture along the walls, one run per wall at most.
    std::shuffle(walls.begin(), walls.end(), rng_);
    for (int f : walls) {
      if (chance(ranges_.p_kitchen) && !kitchen_) {
        kitchen_ = true, addKitchen(f), room.furnished_walls.push_back(f);
      } else if (chance(ranges_.p_shelving)) {
        addShelving(f), room.furnished_walls.push_back(f);
      } else if (chance(ranges_.p_wardrobe)) {
        addFurniture("wardrobe", againstWall(f, along(f, 1.0, 2.0), 0.6, 0.0, uniform(1.9, std::min(2.25, size_.z() - 0.1))));
        room.furnished_walls.push_back(f);
      } else if (chance(ranges_.p_sofa)) {
        addFurniture("sofa", againstWall(f, along(f, 1.6, 2.3), 0.9, 0.0, 0.85));
        room.furnished_walls.push_back(f);
      } else if (chance(ranges_.p_radiator)) {
        addFixture(labelled(againstWall(f, along(f, 0.8, 1.6), 0.1, 0.12, 0.6, 0.04), "radiator"));
      }
    }
    if (chance(ranges_.p_table)) addTableWithChairs();
    addCeilingLights();

    room.truth = model(Eigen::Vector3d::Zero(), size_, rig_yaw, truth_objects_);
    const Eigen::Vector3d lo(recess_depth_[0], recess_depth_[2], 0.0);
    const Eigen::Vector3d grown = size_ + lo + Eigen::Vector3d(recess_depth_[1], recess_depth_[3], 0.0);
    room.scanned = model(lo, grown, rig_yaw, solids_);
    for (CuboidObject pane : model(lo, grown, rig_yaw, panes_).objects) {
      pane.material = "glass_window";
      room.window_panes.push_back(pane);
    }
    return room;
  }

 private:
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }

  // The length of wall f (along the wall, main walls).
  double wallLength(int f) const { return (f - 2) / 2 == 0 ? size_.y() : size_.x(); }
  // A random stretch of wall f of a width in [lo, hi]: its centre along the wall.
  double along(int f, double lo, double hi) {
    width_ = std::min(uniform(lo, hi), wallLength(f) - 0.2);
    return uniform(0.1 + 0.5 * width_, wallLength(f) - 0.1 - 0.5 * width_);
  }

  // An upright cuboid against main wall f: `u` its centre along the wall (width_ wide),
  // `depth` out from the wall after a `gap`, from height z0 up by `height`.
  CuboidObject againstWall(int f, double u, double depth, double z0, double height, double gap = 0.0) const {
    const int axis = (f - 2) / 2;
    const bool high = (f - 2) % 2 == 1;
    CuboidObject box;
        Eigen::Vector3d centre, size;
    centre[axis] = high ? size_[axis] - gap - 0.5 * depth : gap + 0.5 * depth;
    centre[1 - axis] = u;
    centre.z() = z0 + 0.5 * height;
    size[axis] = depth;
    size[1 - axis] = width_;
    size.z() = height;
    box.center_m = centre;
    box.size_m = size;
    return box;
  }

  CuboidObject skirting(int f) {
    width_ = wallLength(f);
    return againstWall(f, 0.5 * width_, 0.015, 0.0, 0.1);
  }

  // A recessed door (or window, from sill height) in wall f: the wall lies recess_depth
  // behind the main plane there; pieces of wall cover the rest of its depth.
  void addRecess(int f, bool window) {
    const double d = recess_depth_[f - 2];
    const int axis = (f - 2) / 2, other = 1 - axis;
    const bool high = (f - 2) % 2 == 1;
    const double hole_width = window ? uniform(1.0, 2.2) : uniform(0.9, 1.8);
    const double u0 = uniform(0.3, std::max(0.31, wallLength(f) - 0.3 - hole_width)), u1 = u0 + hole_width;
    const double z0 = window ? uniform(0.8, 1.0) : 0.0, z1 = window ? uniform(2.0, std::min(2.3, size_.z() - 0.15)) : 2.05;
    // The span along the wall includes the recesses of the walls across.
    const double span_lo = -recess_depth_[2 * other], span_hi = wallLength(f) + recess_depth_[2 * other + 1];
    const auto piece = [&](double a, double b, double za, double zb) {
      if (b - a < 1e-3 || zb - za < 1e-3) return;
      CuboidObject box;
      box.label = "wall";
            Eigen::Vector3d centre, size;
      centre[axis] = high ? size_[axis] + 0.5 * d : -0.5 * d;
      centre[other] = 0.5 * (a + b);
      centre.z() = 0.5 * (za + zb);
      size[axis] = d;
      size[other] = b - a;
      size.z() = zb - za;
      box.center_m = centre;
      box.size_m = size;
      solids_.push_back(box);
    };
    piece(span_lo, u0, 0.0, size_.z());
    piece(u1, span_hi, 0.0, size_.z());
    piece(u0, u1, z1, size_.z());
    piece(u0, u1, 0.0, z0);
    if (window) {
      // The glass at the back of the hole, 2 cm thick, drawing no random number so that the
      // rooms are the same with or without it.
      CuboidObject pane;
      pane.label = "window";
      Eigen::Vector3d centre, size;
      centre[axis] = high ? size_[axis] + d - 0.01 : -d + 0.01;
      centre[other] = 0.5 * (u0 + u1);
      centre.z() = 0.5 * (z0 + z1);
      size[axis] = 0.02;
      size[other] = u1 - u0;
      size.z() = z1 - z0;
      pane.center_m = centre;
      pane.size_m = size;
      panes_.push_back(pane);
    }
  }

  void addKitchen(int f) {
    const double u = along(f, 0.5 * wallLength(f), 0.9 * wallLength(f));
    const double run = width_;
    addFurniture("cabinet", againstWall(f, u, 0.58, 0.0, 0.86));
    addFixture(labelled(againstWall(f, u, 0.62, 0.86, 0.04), "worktop"));
    const bool to_ceiling = chance(0.3);
    const double top = to_ceiling ? size_.z() : std::min(size_.z() - 0.15, 2.2);
    width_ = run * uniform(0.5, 0.9);
    addFurniture("cabinet", againstWall(f, u, 0.35, 1.45, top - 1.45));
    // A tall fridge at one end of the run.
    width_ = 0.6;
    const double end = chance(0.5) ? u - 0.5 * run - 0.35 : u + 0.5 * run + 0.35;
    if (end > 0.35 && end < wallLength(f) - 0.35) addFurniture("fridge", againstWall(f, end, 0.65, 0.0, 1.85));
  }

  void addShelving(int f) {
    const double u = along(f, 0.9, 2.2);
    const double width = width_, depth = 0.3, height = std::min(2.0, size_.z() - 0.2);
    // The frame is what the truth names; what the rig sees is its sides, boards and the
    // clutter on them, with gaps between.
    CuboidObject named = againstWall(f, u, depth, 0.0, height);
    if (nearRig(named)) return;
    named.label = "shelf";
    truth_objects_.push_back(named);
    width_ = 0.02;
    addFixture(labelled(againstWall(f, u - 0.5 * width + 0.01, depth, 0.0, height), "shelf_board"));
    addFixture(labelled(againstWall(f, u + 0.5 * width - 0.01, depth, 0.0, height), "shelf_board"));
    const int boards = 5;
    for (int b = 0; b < boards; ++b) {
      const double z = height * b / (boards - 1) - (b == boards - 1 ? 0.02 : 0.0);
      width_ = width;
      addFixture(labelled(againstWall(f, u, depth, z, 0.02), "shelf_board"));
      if (b == boards - 1) break;
      // Books and boxes on the board.
      double x = u - 0.5 * width + 0.03;
      for (int k = 0; k < ranges_.clutter_per_shelf && x < u + 0.5 * width - 0.1; ++k) {
        width_ = uniform(0.04, 0.3);
        const double gap = uniform(0.0, 0.15);
        if (x + gap + width_ > u + 0.5 * width - 0.03) break;
        addFixture(labelled(againstWall(f, x + gap + 0.5 * width_, uniform(0.15, depth - 0.02), z + 0.02,
                                        uniform(0.12, height / (boards - 1) - 0.06)),
                            "books"));
        x += gap + width_;
      }
    }
  }

  void addTableWithChairs() {
    const double length = uniform(1.2, 2.4), width = uniform(0.7, 1.1), height = uniform(0.72, 0.76);
    const double yaw = chance(0.7) ? 0.0 : uniform(-0.4, 0.4);
    const Eigen::Vector2d centre(uniform(1.2, size_.x() - 1.2), uniform(1.2, size_.y() - 1.2));
    if ((centre - rig_.head<2>()).norm() < 0.5 * std::hypot(length, width) + 1.0) return;
    const Eigen::Matrix2d r = Eigen::Rotation2Dd(yaw).toRotationMatrix();
    const auto at = [&](double lx, double ly) -> Eigen::Vector2d { return centre + r * Eigen::Vector2d(lx, ly); };
    const auto cuboid = [&](const Eigen::Vector2d& c, double sx, double sy, double z0, double sz) {
      CuboidObject box;
            box.center_m = {c.x(), c.y(), z0 + 0.5 * sz};
      box.size_m = {sx, sy, sz};
      box.yaw_rad = yaw;
      return box;
    };
    CuboidObject table = cuboid(centre, length, width, 0.0, height);
    table.label = "table";
    truth_objects_.push_back(table);
    addFixture(labelled(cuboid(centre, length, width, height - 0.04, 0.04), "table_top"));
    for (int sx : {-1, 1}) {
      for (int sy : {-1, 1}) {
        addFixture(labelled(cuboid(at(sx * (0.5 * length - 0.06), sy * (0.5 * width - 0.06)), 0.05, 0.05, 0.0, height - 0.04),
                            "table_leg"));
      }
    }
    // Chairs along both long sides, pulled out a little.
    const int per_side = std::max(1, static_cast<int>(length / 0.65));
    for (int side : {-1, 1}) {
      for (int k = 0; k < per_side; ++k) {
        const double lx = -0.5 * length + (k + 0.5) * length / per_side;
        const double ly = side * (0.5 * width + uniform(0.1, 0.35));
        const Eigen::Vector2d seat = at(lx, ly);
        if ((seat - rig_.head<2>()).norm() < 0.7) continue;
        CuboidObject chair = cuboid(seat, 0.45, 0.45, 0.0, 0.9);
        chair.label = "chair";
        truth_objects_.push_back(chair);
        addFixture(labelled(cuboid(seat, 0.45, 0.45, 0.43, 0.04), "chair_seat"));
        addFixture(labelled(cuboid(at(lx, ly + side * 0.2), 0.45, 0.04, 0.47, 0.43), "chair_back"));
        for (int a : {-1, 1}) {
          for (int b : {-1, 1}) addFixture(labelled(cuboid(at(lx + a * 0.19, ly + b * 0.19), 0.03, 0.03, 0.0, 0.43), "chair_leg"));
        }
      }
    }
  }

  // Panels hanging 0.3-0.5 m below the ceiling on a grid.
  void addCeilingLights() {
    const int nx = std::max(1, static_cast<int>(size_.x() / 2.5)), ny = std::max(1, static_cast<int>(size_.y() / 2.5));
    const double drop = uniform(0.3, 0.5);
    for (int i = 0; i < nx; ++i) {
      for (int j = 0; j < ny; ++j) {
        CuboidObject light;
        light.label = "light";
                light.center_m = {(i + 0.5) * size_.x() / nx, (j + 0.5) * size_.y() / ny, size_.z() - drop};
        light.size_m = {0.6, 0.6, 0.06};
        solids_.push_back(light);
      }
    }
  }

  static CuboidObject labelled(CuboidObject box, const std::string& label) {
    box.label = label;
    return box;
  }

  // The look of each kind of piece (a library material, so that the generator can render
  // it and the simulator hear it).
  static std::string materialOf(const std::string& label) {
    static const std::map<std::string, std::string> kMaterials = {
        {"wall", "plaster_smooth"}, {"skirting", "wood_panel"}, {"radiator", "metal"},
        {"cabinet", "wood_panel"}, {"worktop", "wood_panel"}, {"fridge", "metal"},
        {"wardrobe", "wood_panel"}, {"sofa", "fabric_upholstered_seat"}, {"shelf_board", "wood_panel"},
        {"books", "bookshelf_with_books"}, {"table_top", "wood_panel"}, {"table_leg", "metal"},
        {"chair_seat", "chair_wooden"}, {"chair_back", "chair_wooden"}, {"chair_leg", "metal"},
        {"light", "metal"}, {"shelf", "bookshelf_with_books"}, {"table", "wood_panel"}, {"chair", "chair_wooden"}};
    const auto it = kMaterials.find(label);
    return it == kMaterials.end() ? "wood_panel" : it->second;
  }

  // A solid piece of furniture the truth names; skipped where it would stand within 0.6 m
  // of the rig.
  void addFurniture(const std::string& label, CuboidObject box) {
    if (nearRig(box)) return;
    box.label = label;
    truth_objects_.push_back(box);
    solids_.push_back(box);
  }
  // A solid the rig sees that the truth does not name (wall pieces, fixtures, the parts of
  // a table or a shelf).
  void addFixture(const CuboidObject& box) {
    if (!nearRig(box)) solids_.push_back(box);
  }
  bool nearRig(const CuboidObject& box) const {
    const Eigen::Vector3d d = (rig_ - box.center_m).cwiseAbs() - 0.5 * box.size_m;
    return d.x() < 0.6 && d.y() < 0.6 && d.z() < 0.6;
  }

  // A model whose main-wall corner is at `offset` in its own frame.
  RoomModel model(const Eigen::Vector3d& offset, const Eigen::Vector3d& size, double rig_yaw,
                        const std::vector<CuboidObject>& objects) const {
    RoomModel m;
    m.size_m = size;
    m.has_ceiling = true;
    m.rig_position_m = rig_ + offset;
    m.rig_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(rig_yaw, Eigen::Vector3d::UnitZ()));
    for (CuboidObject o : objects) {
      o.center_m += offset;
      o.material = materialOf(o.label);
      o.confidence = 1.0;
      m.objects.push_back(o);
    }
    m.surfaces = surfaces_;
    return m;
  }

  std::map<std::string, SurfaceAssignment> surfaces_;
  Ranges ranges_;
  std::mt19937 rng_;
  Eigen::Vector3d size_ = Eigen::Vector3d::Zero(), rig_ = Eigen::Vector3d::Zero();
  double recess_depth_[4] = {0.0, 0.0, 0.0, 0.0};  // x_min, x_max, y_min, y_max
  double width_ = 1.0;
  bool kitchen_ = false;
  std::vector<CuboidObject> truth_objects_, solids_, panes_;
};

}  // namespace

ClutteredRoom clutteredRoom(ClutterSet set, int index) {
  const char* family = set == ClutterSet::kDevelopment ? "development" : set == ClutterSet::kHeldOut ? "held-out" : "large development";
  const std::string name = std::string(family) + " room " + std::to_string(index);
  return RoomBuilder(set, index).build(name);
}

}  // namespace room_reverb::core
