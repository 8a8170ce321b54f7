// Readers for the mesh formats room models come in: AC3D (the BRAS database and RAVEN),
// Wavefront OBJ and PLY. They are small line-oriented formats, so they are parsed here
// rather than through a general asset library: the project needs exact error locations
// (file and line) and the AC3D object hierarchy, which such libraries hide or drop.
#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <sstream>

#include "room_reverb/acoustics/triangle_mesh.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"

namespace room_reverb::core {
namespace {

[[noreturn]] void fail(const std::string& path, std::size_t line, const std::string& message) {
  throw InputError(path + ":" + std::to_string(line) + ": " + message);
}

std::string lowerExtension(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

// Lines without their terminator; "\r\n" files (the BRAS model is one) read like "\n" ones.
std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
    start = end + 1;
  }
  return lines;
}

std::vector<std::string> tokens(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  std::string token;
  while (in >> token) out.push_back(token);
  return out;
}

// from_chars rather than strtod/stream extraction: those follow the C locale, and a node
// that sets a locale with a decimal comma would otherwise misread every coordinate.
bool parseDouble(const std::string& token, double& value) {
  const char* begin = token.data();
  const char* end = begin + token.size();
  if (begin != end && *begin == '+') ++begin;
  const auto result = std::from_chars(begin, end, value);
  return result.ec == std::errc() && result.ptr == end;
}

bool parseLong(const std::string& token, long long& value) {
  const char* begin = token.data();
  const char* end = begin + token.size();
  if (begin != end && *begin == '+') ++begin;
  const auto result = std::from_chars(begin, end, value);
  return result.ec == std::errc() && result.ptr == end;
}

double doubleAt(const std::string& token, const std::string& path, std::size_t line,
                const std::string& what) {
  double value = 0.0;
  if (!parseDouble(token, value)) fail(path, line, what + ": '" + token + "' is not a number");
  return value;
}

long long longAt(const std::string& token, const std::string& path, std::size_t line,
                 const std::string& what) {
  long long value = 0;
  if (!parseLong(token, value)) fail(path, line, what + ": '" + token + "' is not an integer");
  return value;
}

// A count (numvert, refs, element size...): a non-negative integer.
std::size_t countAt(const std::string& token, const std::string& path, std::size_t line,
                    const std::string& what) {
  const long long value = longAt(token, path, line, what);
  if (value < 0) fail(path, line, what + " is negative (" + token + ")");
  return static_cast<std::size_t>(value);
}

Eigen::Vector3d finiteVertex(const std::vector<std::string>& t, std::size_t first,
                             const std::string& path, std::size_t line) {
  if (t.size() < first + 3) fail(path, line, "a vertex needs three coordinates");
  const Eigen::Vector3d p(doubleAt(t[first], path, line, "vertex x"),
                          doubleAt(t[first + 1], path, line, "vertex y"),
                          doubleAt(t[first + 2], path, line, "vertex z"));
  if (!p.allFinite()) fail(path, line, "vertex coordinates are not finite");
  return p;
}

// ---------------------------------------------------------------------------------------
// Polygon triangulation.
// ---------------------------------------------------------------------------------------

// Appends the triangles of a planar polygon given by mesh vertex indices (already checked
// to be in range), keeping the polygon's winding. A fan is exact for convex polygons, which
// are nearly all faces in room models; a concave one (an L-shaped floor, a wall around a
// door) gets ear clipping instead, because a fan over it covers area outside the polygon.
void triangulatePolygon(TriangleMesh& mesh, const std::vector<int>& polygon, int material) {
  const std::size_t n = polygon.size();
  if (n < 3) return;
  auto emit = [&](int a, int b, int c) {
    mesh.triangles.push_back({a, b, c});
    mesh.triangle_material.push_back(material);
  };
  auto fan = [&](const std::vector<int>& ring) {
    for (std::size_t i = 1; i + 1 < ring.size(); ++i) emit(ring[0], ring[i], ring[i + 1]);
  };
  if (n == 3) {
    fan(polygon);
    return;
  }

  // Newell's normal is robust for non-convex and slightly non-planar polygons.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(polygon[i])];
    const Eigen::Vector3d& b = mesh.vertices[static_cast<std::size_t>(polygon[(i + 1) % n])];
    normal += a.cross(b);
  }
  if (!(normal.norm() > 0.0)) {
    fan(polygon);  // no area: validateMesh drops whatever the fan yields
    return;
  }
  // Work in the coordinate plane the polygon is most parallel to; with the sign of the
  // dropped axis folded in, the polygon's winding is counter-clockwise in 2D.
  int drop = 0;
  normal.cwiseAbs().maxCoeff(&drop);
  const int u = (drop + 1) % 3;
  const int v = (drop + 2) % 3;
  const double sign = normal[drop] > 0.0 ? 1.0 : -1.0;
  auto point2 = [&](int vertex) {
    const Eigen::Vector3d& p = mesh.vertices[static_cast<std::size_t>(vertex)];
    return Eigen::Vector2d(p[u], p[v]);
  };
  auto turn = [&](int a, int b, int c) {  // > 0 for a left (convex) turn a -> b -> c
    const Eigen::Vector2d ab = point2(b) - point2(a);
    const Eigen::Vector2d bc = point2(c) - point2(b);
    return sign * (ab.x() * bc.y() - ab.y() * bc.x());
  };
  double scale = 0.0;
  for (const int vertex : polygon) scale = std::max(scale, point2(vertex).cwiseAbs().maxCoeff());
  const double eps = 1e-12 * scale * scale;

  bool convex = true;
  for (std::size_t i = 0; i < n && convex; ++i) {
    convex = turn(polygon[i], polygon[(i + 1) % n], polygon[(i + 2) % n]) >= -eps;
  }
  if (convex) {
    fan(polygon);
    return;
  }

  // Ear clipping: cut off a convex corner whose triangle holds no other polygon vertex.
  std::vector<int> ring = polygon;
  auto inside = [&](int p, int a, int b, int c) {
    return turn(a, b, p) >= -eps && turn(b, c, p) >= -eps && turn(c, a, p) >= -eps;
  };
  while (ring.size() > 3) {
    const std::size_t m = ring.size();
    bool clipped = false;
    for (std::size_t i = 0; i < m && !clipped; ++i) {
      const int a = ring[(i + m - 1) % m];
      const int b = ring[i];
      const int c = ring[(i + 1) % m];
      if (turn(a, b, c) <= eps) continue;
      bool empty = true;
      for (std::size_t j = 0; j < m && empty; ++j) {
        const int p = ring[j];
        if (p == a || p == b || p == c) continue;
        if (point2(p) == point2(a) || point2(p) == point2(b) || point2(p) == point2(c)) continue;
        empty = !inside(p, a, b, c);
      }
      if (!empty) continue;
      emit(a, b, c);
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    // A self-intersecting polygon has no ear; a fan over the rest is the best left to do.
    if (!clipped) break;
  }
  fan(ring);
}

// ---------------------------------------------------------------------------------------
// AC3D (AC3Db): http://www.inivis.com/ac3d/man/ac3dfileformat.html
// ---------------------------------------------------------------------------------------

class Ac3dReader {
 public:
  Ac3dReader(const std::string& path, const std::string& text)
      : path_(path), lines_(splitLines(text)) {}

  TriangleMesh read() {
    if (lines_.empty() || lines_[0].rfind("AC3D", 0) != 0) {
      fail(path_, 1, "not an AC3D file (the first line should start with AC3D)");
    }
    next_ = 1;
    std::vector<std::string> t;
    std::size_t line = 0;
    while (nextTokens(t, line)) {
      if (t[0] == "MATERIAL") {
        material_map_.push_back(mesh_.materialIndex(quotedName(line)));
      } else if (t[0] == "OBJECT") {
        readObject(Eigen::Affine3d::Identity(), line);
      } else {
        fail(path_, line, "expected MATERIAL or OBJECT, found '" + t[0] + "'");
      }
    }
    return std::move(mesh_);
  }

 private:
  // Next non-blank line as tokens; false at the end of the file.
  bool nextTokens(std::vector<std::string>& t, std::size_t& line) {
    while (next_ < lines_.size()) {
      line = next_ + 1;
      t = tokens(lines_[next_++]);
      if (!t.empty()) return true;
    }
    return false;
  }

  // Like nextTokens, for lines a count promised: the end of the file is an error.
  std::vector<std::string> requireTokens(std::size_t& line, const std::string& expected) {
    std::vector<std::string> t;
    if (!nextTokens(t, line)) fail(path_, lines_.size(), "file ends where " + expected + " was expected");
    return t;
  }

  // The name between the first pair of double quotes (names may contain spaces).
  std::string quotedName(std::size_t line) const {
    const std::string& text = lines_[line - 1];
    const auto open = text.find('"');
    const auto close = open == std::string::npos ? open : text.find('"', open + 1);
    if (close == std::string::npos) fail(path_, line, "expected a name in double quotes");
    return text.substr(open + 1, close - open - 1);
  }

  int meshMaterial(long long ac_index, std::size_t line) {
    if (material_map_.empty()) {
      // Files without MATERIAL lines are legal; their surfaces share one unnamed material.
      if (ac_index == 0) return mesh_.materialIndex("default");
    } else if (ac_index >= 0 && ac_index < static_cast<long long>(material_map_.size())) {
      return material_map_[static_cast<std::size_t>(ac_index)];
    }
    fail(path_, line, "material index " + std::to_string(ac_index) + " is out of range (" +
                          std::to_string(material_map_.size()) + " MATERIAL lines)");
  }

  void readObject(const Eigen::Affine3d& parent, std::size_t object_line) {
    Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();
    Eigen::Vector3d loc = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> local;
    struct Polygon {
      std::vector<long long> refs;  // indices into this object's vertices
      long long material;
      std::size_t line;  // of its mat line, else of its SURF line
    };
    std::vector<Polygon> polygons;

    std::vector<std::string> t;
    std::size_t line = object_line;
    while (true) {
      if (!nextTokens(t, line)) fail(path_, lines_.size(), "file ends inside the OBJECT of line " +
                                                               std::to_string(object_line) + " (no kids line)");
      const std::string& key = t[0];
      if (key == "rot") {
        if (t.size() < 10) fail(path_, line, "rot needs nine numbers");
        // Read row by row and applied as p' = rot * p. The format's description leaves the
        // order open; exporters rarely write anything but the identity (they bake rotations
        // into the vertices), so the choice matters little in practice.
        for (int k = 0; k < 9; ++k) rot(k / 3, k % 3) = doubleAt(t[static_cast<std::size_t>(k) + 1], path_, line, "rot");
        if (!rot.allFinite()) fail(path_, line, "rot is not finite");
      } else if (key == "loc") {
        if (t.size() < 4) fail(path_, line, "loc needs three numbers");
        loc = finiteVertex(t, 1, path_, line);
      } else if (key == "numvert") {
        if (t.size() < 2) fail(path_, line, "numvert needs a count");
        const std::size_t count = countAt(t[1], path_, line, "numvert");
        for (std::size_t k = 0; k < count; ++k) {
          std::size_t vertex_line = 0;
          const auto vt = requireTokens(vertex_line, "vertex " + std::to_string(k + 1) + " of " + std::to_string(count));
          local.push_back(finiteVertex(vt, 0, path_, vertex_line));
        }
      } else if (key == "numsurf") {
        if (t.size() < 2) fail(path_, line, "numsurf needs a count");
        const std::size_t count = countAt(t[1], path_, line, "numsurf");
        for (std::size_t k = 0; k < count; ++k) readSurface(polygons, local.size(), k, count);
      } else if (key == "kids") {
        if (t.size() < 2) fail(path_, line, "kids needs a count");
        const std::size_t kids = countAt(t[1], path_, line, "kids");
        // loc and rot place this object within its parent; children inherit the result.
        Eigen::Affine3d world = parent;
        world.translate(loc);
        world.linear() = world.linear() * rot;
        const int base = static_cast<int>(mesh_.vertices.size());
        for (const Eigen::Vector3d& p : local) mesh_.vertices.push_back(world * p);
        for (const Polygon& polygon : polygons) addPolygon(polygon.refs, polygon.material, polygon.line, base);
        for (std::size_t k = 0; k < kids; ++k) {
          std::size_t kid_line = 0;
          const auto kt = requireTokens(kid_line, "OBJECT " + std::to_string(k + 1) + " of " + std::to_string(kids));
          if (kt[0] != "OBJECT") fail(path_, kid_line, "expected OBJECT (child " + std::to_string(k + 1) + " of " +
                                                           std::to_string(kids) + "), found '" + kt[0] + "'");
          readObject(world, kid_line);
        }
        return;
      } else if (key == "data") {
        // data N is followed by N characters of free text, possibly over several lines.
        if (t.size() < 2) fail(path_, line, "data needs a length");
        std::size_t remaining = countAt(t[1], path_, line, "data");
        while (remaining > 0 && next_ < lines_.size()) {
          const std::size_t taken = std::min(remaining, lines_[next_].size());
          remaining -= taken;
          remaining -= remaining > 0 ? 1 : 0;  // the line break counts as a character
          ++next_;
        }
      } else if (std::isalpha(static_cast<unsigned char>(key[0]))) {
        // name, texture, texrep, texoff, crease, url, subdiv, hidden, locked, folded and
        // tokens of later AC3D versions: appearance and editor state, no acoustic meaning.
        // The format's description says a loader may skip them.
      } else {
        fail(path_, line, "unexpected '" + key + "' in an OBJECT (does a count above match its lines?)");
      }
    }
  }

  template <typename Polygon>
  void readSurface(std::vector<Polygon>& polygons, std::size_t vertex_count, std::size_t k,
                   std::size_t count) {
    std::size_t line = 0;
    auto t = requireTokens(line, "SURF " + std::to_string(k + 1) + " of " + std::to_string(count));
    if (t[0] != "SURF" || t.size() < 2) {
      fail(path_, line, "expected SURF (surface " + std::to_string(k + 1) + " of " + std::to_string(count) +
                            "), found '" + t[0] + "'");
    }
    const std::string flags_text = t[1];
    const long long flags = parseFlags(flags_text, line);
    const std::size_t surf_line = line;
    Polygon polygon{{}, 0, surf_line};
    while (true) {
      t = requireTokens(line, "mat or refs of the SURF of line " + std::to_string(surf_line));
      if (t[0] == "mat") {
        if (t.size() < 2) fail(path_, line, "mat needs an index");
        polygon.material = longAt(t[1], path_, line, "mat");
        polygon.line = line;  // a bad index is reported where it was written
      } else if (t[0] == "refs") {
        if (t.size() < 2) fail(path_, line, "refs needs a count");
        const std::size_t refs = countAt(t[1], path_, line, "refs");
        for (std::size_t r = 0; r < refs; ++r) {
          std::size_t ref_line = 0;
          const auto rt = requireTokens(ref_line, "ref " + std::to_string(r + 1) + " of " + std::to_string(refs));
          const long long index = longAt(rt[0], path_, ref_line, "vertex index");
          if (index < 0 || index >= static_cast<long long>(vertex_count)) {
            fail(path_, ref_line, "vertex index " + std::to_string(index) + " is out of range (the object has " +
                                      std::to_string(vertex_count) + " vertices)");
          }
          polygon.refs.push_back(index);
        }
        break;
      } else {
        fail(path_, line, "expected mat or refs in a SURF, found '" + t[0] + "'");
      }
    }
    // The low four flag bits are the surface type: 0 polygon, 1 closed line, 2 line.
    // Lines are drawing aids with no area, so they are skipped.
    const long long type = flags & 0xF;
    if (type == 1 || type == 2) return;
    if (type != 0) fail(path_, surf_line, "unsupported SURF type " + std::to_string(type) + " (flags " + flags_text + ")");
    polygons.push_back(std::move(polygon));
  }

  long long parseFlags(const std::string& token, std::size_t line) const {
    long long flags = 0;
    const bool hex = token.size() > 2 && token[0] == '0' && (token[1] == 'x' || token[1] == 'X');
    const char* begin = token.data() + (hex ? 2 : 0);
    const char* end = token.data() + token.size();
    const auto result = std::from_chars(begin, end, flags, hex ? 16 : 10);
    if (result.ec != std::errc() || result.ptr != end) fail(path_, line, "SURF flags '" + token + "' are not a number");
    return flags;
  }

  void addPolygon(const std::vector<long long>& refs, long long material, std::size_t line, int base) {
    const int mesh_material = meshMaterial(material, line);
    std::vector<int> polygon;
    polygon.reserve(refs.size());
    for (const long long r : refs) polygon.push_back(base + static_cast<int>(r));
    triangulatePolygon(mesh_, polygon, mesh_material);
  }

  std::string path_;
  std::vector<std::string> lines_;
  std::size_t next_ = 0;
  std::vector<int> material_map_;  // AC3D material index -> mesh material index
  TriangleMesh mesh_;
};

// ---------------------------------------------------------------------------------------
// Wavefront OBJ.
// ---------------------------------------------------------------------------------------

TriangleMesh readObj(const std::string& path, const std::string& text) {
  TriangleMesh mesh;
  const std::vector<std::string> lines = splitLines(text);
  int material = -1;  // faces before any usemtl get "default"
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::size_t line = i + 1;
    std::string content = lines[i];
    const auto hash = content.find('#');
    if (hash != std::string::npos) content.resize(hash);
    const auto t = tokens(content);
    if (t.empty()) continue;
    if (t[0] == "v") {
      // A fourth (w) coordinate is allowed by the format and ignored: no room model uses it.
      mesh.vertices.push_back(finiteVertex(t, 1, path, line));
    } else if (t[0] == "f") {
      if (t.size() < 4) fail(path, line, "a face needs at least three vertices");
      std::vector<int> polygon;
      for (std::size_t k = 1; k < t.size(); ++k) {
        // v, v/vt, v//vn or v/vt/vn: only the position index matters here.
        const std::string index_text = t[k].substr(0, t[k].find('/'));
        const long long index = longAt(index_text, path, line, "face vertex");
        const auto count = static_cast<long long>(mesh.vertices.size());
        // Positive indices count from 1, negative ones back from the latest vertex.
        const long long resolved = index > 0 ? index - 1 : count + index;
        if (index == 0 || resolved < 0 || resolved >= count) {
          fail(path, line, "face vertex " + std::to_string(index) + " is out of range (" +
                               std::to_string(count) + " vertices so far; indices start at 1)");
        }
        polygon.push_back(static_cast<int>(resolved));
      }
      if (material < 0) material = mesh.materialIndex("default");
      triangulatePolygon(mesh, polygon, material);
    } else if (t[0] == "usemtl") {
      const auto start = content.find_first_not_of(" \t", content.find("usemtl") + 6);
      if (start == std::string::npos) fail(path, line, "usemtl needs a material name");
      std::string name = content.substr(start);
      name.erase(name.find_last_not_of(" \t") + 1);
      material = mesh.materialIndex(name);
    }
    // vt, vn, o, g, s, l, p, mtllib...: texture, shading and grouping, no acoustic meaning.
  }
  return mesh;
}

// ---------------------------------------------------------------------------------------
// PLY (ascii and binary_little_endian): http://paulbourke.net/dataformats/ply/
// ---------------------------------------------------------------------------------------

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

bool plyTypeOf(const std::string& name, PlyType& type) {
  static const std::map<std::string, PlyType> kTypes = {
      {"char", PlyType::kInt8},     {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},   {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16}, {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},   {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32}, {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  const auto it = kTypes.find(name);
  if (it == kTypes.end()) return false;
  type = it->second;
  return true;
}

std::size_t plySize(PlyType type) {
  switch (type) {
    case PlyType::kInt8: case PlyType::kUint8: return 1;
    case PlyType::kInt16: case PlyType::kUint16: return 2;
    case PlyType::kInt32: case PlyType::kUint32: case PlyType::kFloat32: return 4;
    case PlyType::kFloat64: return 8;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t line = 0;
};

// Values of the body, one at a time, from text lines (one element instance per line) or
// from little-endian binary; `where()` names the place for error messages.
class PlyBody {
 public:
  PlyBody(const std::string& path, const std::string& text, std::size_t offset, bool binary,
          std::size_t first_line)
      : path_(path), text_(text), pos_(offset), binary_(binary), line_(first_line - 1) {}

  // Called before each element instance.
  void beginInstance(const std::string& element, std::size_t index) {
    element_ = element;
    index_ = index;
    if (binary_) return;
    if (!tokens_.empty() && token_ < tokens_.size()) {
      fail(path_, line_, "more values than the header's properties of " + element_ + " declare");
    }
    tokens_.clear();
    token_ = 0;
    while (tokens_.empty()) {
      if (pos_ >= text_.size()) {
        throw InputError(path_ + ": file ends at " + element_ + " " + std::to_string(index_) +
                         " (the header promised more)");
      }
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string::npos) end = text_.size();
      tokens_ = tokens(text_.substr(pos_, end - pos_));
      pos_ = end + 1;
      ++line_;
    }
  }

  double value(PlyType type) {
    if (!binary_) {
      if (token_ >= tokens_.size()) fail(path_, line_, "too few values for " + element_);
      return doubleAt(tokens_[token_++], path_, line_, element_ + " value");
    }
    const std::size_t size = plySize(type);
    if (pos_ + size > text_.size()) {
      throw InputError(path_ + ": file ends inside " + element_ + " " + std::to_string(index_) +
                       " (the header promised more data)");
    }
    // Assembled byte by byte so the reader does not depend on the host's byte order.
    std::uint64_t bits = 0;
    for (std::size_t b = 0; b < size; ++b) {
      bits |= static_cast<std::uint64_t>(static_cast<unsigned char>(text_[pos_ + b])) << (8 * b);
    }
    pos_ += size;
    switch (type) {
      case PlyType::kInt8: return static_cast<std::int8_t>(bits);
      case PlyType::kUint8: return static_cast<std::uint8_t>(bits);
      case PlyType::kInt16: return static_cast<std::int16_t>(bits);
      case PlyType::kUint16: return static_cast<std::uint16_t>(bits);
      case PlyType::kInt32: return static_cast<std::int32_t>(bits);
      case PlyType::kUint32: return static_cast<std::uint32_t>(bits);
      case PlyType::kFloat32: {
        const auto word = static_cast<std::uint32_t>(bits);
        float f = 0.0f;
        static_assert(sizeof f == sizeof word, "float is 32 bits");
        std::memcpy(&f, &word, sizeof f);
        return f;
      }
      case PlyType::kFloat64: {
        double d = 0.0;
        static_assert(sizeof d == sizeof bits, "double is 64 bits");
        std::memcpy(&d, &bits, sizeof d);
        return d;
      }
    }
    return 0.0;
  }

  // "path:line" for text, "path: <element> <index>" for binary.
  std::string where() const {
    if (binary_) return path_ + ": " + element_ + " " + std::to_string(index_);
    return path_ + ":" + std::to_string(line_);
  }

 private:
  const std::string& path_;
  const std::string& text_;
  std::size_t pos_;
  bool binary_;
  std::size_t line_;
  std::string element_;
  std::size_t index_ = 0;
  std::vector<std::string> tokens_;
  std::size_t token_ = 0;
};

std::string shortNumber(double value) {
  std::ostringstream os;
  os << value;
  return os.str();
}

// ASCII PLY holds every number as text, so an integer property may read as 1e30; casting
// that to an integer type would be undefined, hence the explicit range check.
bool integral(double value, long long& out) {
  if (!(std::abs(value) <= 9007199254740992.0) || value != std::floor(value)) return false;  // 2^53
  out = static_cast<long long>(value);
  return true;
}

// No face in a room model has anywhere near this many corners; a larger count is corrupt.
constexpr long long kMaxListCount = 1 << 20;

TriangleMesh readPly(const std::string& path, const std::string& text) {
  // Header: text lines up to end_header.
  std::size_t pos = 0;
  std::size_t line = 0;
  auto nextHeaderLine = [&]() {
    if (pos >= text.size()) fail(path, line, "the header has no end_header line");
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string l = text.substr(pos, end - pos);
    if (!l.empty() && l.back() == '\r') l.pop_back();
    pos = end + 1;
    ++line;
    return l;
  };
  if (nextHeaderLine() != "ply") fail(path, 1, "not a PLY file (the first line should be 'ply')");
  bool binary = false;
  bool have_format = false;
  std::vector<PlyElement> elements;
  std::map<long long, std::string> material_names;
  while (true) {
    const std::string l = nextHeaderLine();
    const auto t = tokens(l);
    if (t.empty()) continue;
    if (t[0] == "end_header") break;
    if (t[0] == "format") {
      if (t.size() < 2) fail(path, line, "format needs a name");
      if (t[1] == "ascii") {
        binary = false;
      } else if (t[1] == "binary_little_endian") {
        binary = true;
      } else if (t[1] == "binary_big_endian") {
        fail(path, line, "binary_big_endian PLY is not supported; save it as ascii or binary_little_endian");
      } else {
        fail(path, line, "unknown PLY format '" + t[1] + "'");
      }
      have_format = true;
    } else if (t[0] == "comment") {
      if (t.size() >= 4 && t[1] == "material") {
        const long long index = longAt(t[2], path, line, "material comment index");
        // The name is the rest of the line, so it may contain spaces.
        const auto at = l.find(t[3], l.find(t[2], l.find("material") + 8) + t[2].size());
        std::string name = l.substr(at);
        name.erase(name.find_last_not_of(" \t") + 1);
        material_names[index] = name;
      }
    } else if (t[0] == "obj_info") {
      // Free text.
    } else if (t[0] == "element") {
      if (t.size() < 3) fail(path, line, "element needs a name and a count");
      elements.push_back({t[1], countAt(t[2], path, line, "element count"), {}, line});
    } else if (t[0] == "property") {
      if (elements.empty()) fail(path, line, "property before any element");
      PlyProperty property;
      if (t.size() >= 2 && t[1] == "list") {
        if (t.size() < 5) fail(path, line, "property list needs a count type, an item type and a name");
        property.is_list = true;
        if (!plyTypeOf(t[2], property.count_type)) fail(path, line, "unknown PLY type '" + t[2] + "'");
        if (!plyTypeOf(t[3], property.type)) fail(path, line, "unknown PLY type '" + t[3] + "'");
        property.name = t[4];
      } else {
        if (t.size() < 3) fail(path, line, "property needs a type and a name");
        if (!plyTypeOf(t[1], property.type)) fail(path, line, "unknown PLY type '" + t[1] + "'");
        property.name = t[2];
      }
      elements.back().properties.push_back(property);
    } else {
      fail(path, line, "unexpected '" + t[0] + "' in the PLY header");
    }
  }
  if (!have_format) fail(path, line, "the header has no format line");

  TriangleMesh mesh;
  struct Face {
    std::vector<long long> indices;
    long long material;
    std::string where;
  };
  std::vector<Face> faces;
  bool faces_have_material = false;
  PlyBody body(path, text, pos, binary, line + 1);
  for (const PlyElement& element : elements) {
    auto find = [&](const std::string& name) {
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        if (element.properties[p].name == name) return static_cast<int>(p);
      }
      return -1;
    };
    const bool is_vertex = element.name == "vertex";
    const bool is_face = element.name == "face";
    const int px = find("x"), py = find("y"), pz = find("z");
    int pindices = find("vertex_indices");
    if (pindices < 0) pindices = find("vertex_index");
    const int pmaterial = find("material_index");
    if (is_vertex && (px < 0 || py < 0 || pz < 0)) {
      fail(path, element.line, "element vertex needs properties x, y and z");
    }
    if (is_face && (pindices < 0 || !element.properties[static_cast<std::size_t>(pindices)].is_list)) {
      fail(path, element.line, "element face needs a list property vertex_indices");
    }
    if (is_face && pmaterial >= 0) faces_have_material = true;
    for (std::size_t i = 0; i < element.count; ++i) {
      body.beginInstance(element.name, i);
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      Face face{{}, 0, ""};
      for (std::size_t k = 0; k < element.properties.size(); ++k) {
        const PlyProperty& property = element.properties[k];
        const int pk = static_cast<int>(k);
        if (property.is_list) {
          long long count = 0;
          if (!integral(body.value(property.count_type), count) || count < 0 || count > kMaxListCount) {
            throw InputError(body.where() + ": the list count of " + property.name + " is not a count");
          }
          for (long long j = 0; j < count; ++j) {
            const double item = body.value(property.type);
            if (is_face && pk == pindices) {
              long long index = 0;
              if (!integral(item, index)) throw InputError(body.where() + ": vertex index " + shortNumber(item) + " is not an integer");
              face.indices.push_back(index);
            }
          }
          continue;
        }
        const double value = body.value(property.type);
        if (is_vertex && pk == px) p.x() = value;
        if (is_vertex && pk == py) p.y() = value;
        if (is_vertex && pk == pz) p.z() = value;
        if (is_face && pk == pmaterial && !integral(value, face.material)) {
          throw InputError(body.where() + ": material_index " + shortNumber(value) + " is not an integer");
        }
      }
      if (is_vertex) {
        if (!p.allFinite()) throw InputError(body.where() + ": vertex " + std::to_string(i) + " is not finite");
        mesh.vertices.push_back(p);
      }
      if (is_face) {
        face.where = body.where();
        faces.push_back(std::move(face));
      }
    }
  }

  // Faces are resolved after every element is read: the format does not require the vertex
  // element to come first.
  const auto vertex_count = static_cast<long long>(mesh.vertices.size());
  for (const Face& face : faces) {
    if (face.indices.size() < 3) throw InputError(face.where + ": a face needs at least three vertices");
    std::vector<int> polygon;
    for (const long long index : face.indices) {
      if (index < 0 || index >= vertex_count) {
        throw InputError(face.where + ": vertex index " + std::to_string(index) + " is out of range (" +
                         std::to_string(vertex_count) + " vertices)");
      }
      polygon.push_back(static_cast<int>(index));
    }
    std::string name = "default";
    if (faces_have_material) {
      const auto it = material_names.find(face.material);
      name = it != material_names.end() ? it->second : "material_" + std::to_string(face.material);
    }
    triangulatePolygon(mesh, polygon, mesh.materialIndex(name));
  }
  return mesh;
}

}  // namespace

TriangleMesh loadMesh(const std::string& path, UpAxis up) {
  const std::string ext = lowerExtension(path);
  if (ext != "ac" && ext != "obj" && ext != "ply") {
    throw InputError(path + ": unknown mesh format '." + ext + "' (use .ac, .obj or .ply)");
  }
  const std::string text = readTextFile(path, "mesh file");
  TriangleMesh mesh;
  if (ext == "ac") {
    mesh = Ac3dReader(path, text).read();
  } else if (ext == "obj") {
    mesh = readObj(path, text);
  } else {
    mesh = readPly(path, text);
  }
  if (up == UpAxis::kY) {
    for (Eigen::Vector3d& p : mesh.vertices) p = yUpToZUp(p);
  }
  validateMesh(mesh, path);
  return mesh;
}

}  // namespace room_reverb::core
