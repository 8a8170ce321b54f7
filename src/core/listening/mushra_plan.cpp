// Reading and checking a MUSHRA plan: everything that can be wrong with a plan is found
// here, before any rendering starts, so a bad plan costs seconds, not a render of every
// stimulus that ends in an error.
#include "room_reverb/listening/mushra_plan.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "room_reverb/binaural/hrtf_set.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/common/yaml_reader.h"

namespace room_reverb::core {
namespace {

const std::vector<std::string> kNeedRir = {"reference", "rsao", "lowpass_3k5"};
const std::vector<std::string> kNeedModel = {"fast", "accurate"};
// The conditions that are anchors when the plan does not say which are.
const std::vector<std::string> kDefaultAnchors = {"reference", "wrong_room", "lowpass_3k5"};

bool contains(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// Names become folder and file names in DIR and keys of the page's results, so they are
// kept to characters that are safe in all three.
bool isSafeName(const std::string& name) {
  if (name.empty() || name == "." || name == "..") return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
  });
}

class MushraPlanReader : public YamlReader {
 public:
  MushraPlanReader(std::string source, std::string base) : YamlReader(std::move(source)), base_(std::move(base)) {}

  MushraPlan parse(const std::string& yaml_text) const {
    return guarded("MUSHRA plan", [&] { return parseUnguarded(yaml_text); });
  }

 private:
  MushraPlan parseUnguarded(const std::string& yaml_text) const {
    const YAML::Node root = loadMap(yaml_text, "a MUSHRA plan (rooms, contents, attributes, conditions)");
    checkKeys(root, "plan",
              {"seed", "scale", "duration_s", "loudness_lufs", "max_peak_dbfs", "hrtf", "decoder", "simulation", "rooms",
               "contents", "attributes", "conditions", "hidden_anchors", "shown_references"});
    MushraPlan plan;
    plan.source = source();
    plan.seed = seed(root);
    const std::string scale = textOr(root, "scale", "scale", "0-5");
    try {
      plan.scale = parseMushraScale(scale);
    } catch (const InputError&) {
      fail(root["scale"], "scale", "must be 0-5 or 0-100 (got " + scale + ")");
    }
    if (root["duration_s"].IsDefined() && !root["duration_s"].IsNull()) {
      plan.duration_s = number(root["duration_s"], "duration_s");
      if (*plan.duration_s < 0.4) {
        fail(root["duration_s"], "duration_s", "must be at least 0.4 s, the block over which loudness is measured");
      }
    }
    plan.loudness_lufs = numberOr(root, "loudness_lufs", "loudness_lufs", plan.loudness_lufs);
    if (!(plan.loudness_lufs >= -70.0 && plan.loudness_lufs < 0.0)) {
      fail(root["loudness_lufs"], "loudness_lufs", "must lie between -70 and 0 LUFS");
    }
    plan.max_peak_dbfs = numberOr(root, "max_peak_dbfs", "max_peak_dbfs", plan.max_peak_dbfs);
    if (!(plan.max_peak_dbfs <= 0.0)) fail(root["max_peak_dbfs"], "max_peak_dbfs", "must be 0 dBFS or below");
    plan.hrtf = root["hrtf"].IsDefined() ? file(root["hrtf"], "hrtf", "HRTF set (SOFA)") : HrtfSet::defaultSofaPath();
    requireExistingFile(plan.hrtf, "HRTF set (SOFA)");
    const std::string decoder = textOr(root, "decoder", "decoder", "magls");
    try {
      plan.decoder = parseDecoderMethod(decoder);
    } catch (const InputError&) {
      fail(root["decoder"], "decoder", "must be magls, least_squares or virtual_loudspeakers (got " + decoder + ")");
    }
    if (root["simulation"].IsDefined()) plan.simulation = simulation(root["simulation"]);

    plan.conditions = conditions(root);
    const YAML::Node rooms = sequence(root, "rooms"), contents = sequence(root, "contents"),
                     attributes = sequence(root, "attributes");
    for (std::size_t i = 0; i < rooms.size(); ++i) plan.rooms.push_back(room(rooms, i));
    for (std::size_t i = 0; i < contents.size(); ++i) plan.contents.push_back(content(contents, i));
    for (std::size_t i = 0; i < attributes.size(); ++i) plan.attributes.push_back(attribute(attributes, i));
    requireUnique(root["rooms"], "rooms", plan.rooms, [](const MushraRoom& r) { return r.name; });
    requireUnique(root["contents"], "contents", plan.contents, [](const MushraContent& c) { return c.name; });
    requireUnique(root["attributes"], "attributes", plan.attributes, [](const MushraAttribute& a) { return a.id; });

    plan.hidden_anchors = anchors(root, plan.conditions);
    plan.shown_references = shownReferences(root, plan.conditions);
    checkRoomsServeConditions(root, plan);
    resolveWrongRooms(root, plan);
    return plan;
  }

  void checkKeys(const YAML::Node& node, const std::string& key, const std::vector<std::string>& known) const {
    for (const auto& entry : node) {
      const std::string name = entry.first.Scalar();
      if (!contains(known, name)) fail(entry.first, key, "unknown key '" + name + "' (known: " + joined(known) + ")");
    }
  }

  std::uint32_t seed(const YAML::Node& root) const {
    const double value = number(require(root, "seed", "seed", "missing: every random choice of the test needs one"),
                                "seed");
    if (value < 0.0 || value > 4294967295.0 || value != std::floor(value)) {
      fail(root["seed"], "seed", "must be a whole number from 0 to 4294967295");
    }
    return static_cast<std::uint32_t>(value);
  }

  int wholeNumber(const YAML::Node& parent, const std::string& name, const std::string& key, int fallback, int low,
                  int high) const {
    const double value = numberOr(parent, name, key, fallback);
    if (value != std::floor(value) || value < low || value > high) {
      fail(parent[name], key, "must be a whole number from " + std::to_string(low) + " to " + std::to_string(high));
    }
    return static_cast<int>(value);
  }

  MushraSimulation simulation(const YAML::Node& node) const {
    requireMap(node, "simulation");
    checkKeys(node, "simulation", {"rays", "image_source_order", "ambisonic_order", "duration_s", "threads"});
    MushraSimulation s;
    s.rays = wholeNumber(node, "rays", "simulation.rays", s.rays, 1, 100000000);
    s.image_source_order = wholeNumber(node, "image_source_order", "simulation.image_source_order",
                                       s.image_source_order, 0, 20);
    s.ambisonic_order = wholeNumber(node, "ambisonic_order", "simulation.ambisonic_order", s.ambisonic_order, 0, 3);
    s.threads = wholeNumber(node, "threads", "simulation.threads", s.threads, 0, 1024);
    s.duration_s = numberOr(node, "duration_s", "simulation.duration_s", s.duration_s);
    if (!(s.duration_s > 0.0 && s.duration_s <= 60.0)) {
      fail(node["duration_s"], "simulation.duration_s", "must lie between 0 and 60 s");
    }
    return s;
  }

  YAML::Node sequence(const YAML::Node& root, const std::string& name) const {
    const YAML::Node node = require(root, name, name, "missing: a test needs at least one");
    if (!node.IsSequence()) fail(node, name, "must be a list");
    if (node.size() == 0) fail(node, name, "is empty: a test needs at least one");
    return node;
  }

  std::vector<std::string> nameList(const YAML::Node& node, const std::string& key) const {
    if (!node.IsSequence()) fail(node, key, "must be a list of names");
    std::vector<std::string> names;
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string name = text(node[i], key + "[" + std::to_string(i) + "]");
      if (contains(names, name)) fail(node[i], key, "names '" + name + "' twice");
      names.push_back(name);
    }
    return names;
  }

  std::string file(const YAML::Node& node, const std::string& key, const std::string& what) const {
    std::string path = text(node, key);
    if (path.front() != '/') path = (std::filesystem::path(base_) / path).lexically_normal().string();
    if (!std::filesystem::is_regular_file(path)) {
      fail(node, key, path + ": no such file (expected a " + what + ")");
    }
    return path;
  }

  std::string safeName(const YAML::Node& parent, const std::string& name, const std::string& key) const {
    const std::string value = text(require(parent, name, key), key);
    if (!isSafeName(value)) {
      fail(parent[name], key, "'" + value + "' must consist of letters, digits, '_', '-' and '.' (it names files)");
    }
    return value;
  }

  std::vector<std::string> conditions(const YAML::Node& root) const {
    const YAML::Node node = sequence(root, "conditions");
    const std::vector<std::string> names = nameList(node, "conditions");
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (!contains(mushraConditionNames(), names[i])) {
        fail(node[i], "conditions[" + std::to_string(i) + "]",
             "unknown condition '" + names[i] + "' (known: " + joined(mushraConditionNames()) + ")");
      }
    }
    if (names.size() > 26) fail(node, "conditions", "more than 26 conditions cannot have letters A-Z");
    return names;
  }

  MushraRoom room(const YAML::Node& list, std::size_t index) const {
    const YAML::Node node = list[index];
    std::string key = "rooms[" + std::to_string(index) + "]";
    requireMap(node, key);
    checkKeys(node, key,
              {"name", "bformat_rir", "format", "room", "source_m", "listener_m", "panorama", "wrong_room_of"});
    MushraRoom r;
    r.name = safeName(node, "name", key + ".name");
    key += " (" + r.name + ")";
    if (node["bformat_rir"].IsDefined()) {
      r.bformat_rir = file(node["bformat_rir"], key + ".bformat_rir", "B-format RIR");
      const std::string format = text(require(node, "format", key + ".format",
                                              "missing: say whether bformat_rir is fuma or ambix (never guessed)"),
                                      key + ".format");
      try {
        r.format = parseAmbisonicFormat(format);
      } catch (const InputError&) {
        fail(node["format"], key + ".format", "must be fuma or ambix (got " + format + ")");
      }
    }
    if (node["room"].IsDefined()) r.room_model = file(node["room"], key + ".room", "room model (room.yaml)");
    if (node["source_m"].IsDefined()) r.source_m = vector3(node["source_m"], key + ".source_m");
    if (node["listener_m"].IsDefined()) r.listener_m = vector3(node["listener_m"], key + ".listener_m");
    if (node["panorama"].IsDefined()) r.panorama = file(node["panorama"], key + ".panorama", "panorama image");
    if (node["wrong_room_of"].IsDefined()) r.wrong_room_of = text(node["wrong_room_of"], key + ".wrong_room_of");
    return r;
  }

  MushraContent content(const YAML::Node& list, std::size_t index) const {
    const YAML::Node node = list[index];
    std::string key = "contents[" + std::to_string(index) + "]";
    requireMap(node, key);
    checkKeys(node, key, {"name", "file"});
    MushraContent c;
    c.name = safeName(node, "name", key + ".name");
    key += " (" + c.name + ")";
    c.file = file(require(node, "file", key + ".file", "missing: the dry recording"), key + ".file", "dry recording");
    return c;
  }

  MushraAttribute attribute(const YAML::Node& list, std::size_t index) const {
    const YAML::Node node = list[index];
    const std::string key = "attributes[" + std::to_string(index) + "]";
    requireMap(node, key);
    checkKeys(node, key, {"id", "question", "show_panorama"});
    MushraAttribute a;
    a.id = safeName(node, "id", key + ".id");
    a.question = text(require(node, "question", key + ".question", "missing: what the page asks"), key + ".question");
    a.show_panorama = flagOr(node, "show_panorama", key + ".show_panorama", a.id == "spatial_impression");
    return a;
  }

  std::vector<std::string> anchors(const YAML::Node& root, const std::vector<std::string>& conditions) const {
    std::vector<std::string> names;
    if (root["hidden_anchors"].IsDefined()) {
      names = nameList(root["hidden_anchors"], "hidden_anchors");
      requireConditions(root["hidden_anchors"], "hidden_anchors", names, conditions);
    } else {
      for (const std::string& name : kDefaultAnchors) {
        if (contains(conditions, name)) names.push_back(name);
      }
    }
    if (names.empty()) {
      fail(root["hidden_anchors"].IsDefined() ? root["hidden_anchors"] : root["conditions"], "hidden_anchors",
           "a MUSHRA test needs at least one hidden anchor (reference, wrong_room or lowpass_3k5)");
    }
    return names;
  }

  std::vector<std::string> shownReferences(const YAML::Node& root, const std::vector<std::string>& conditions) const {
    if (!root["shown_references"].IsDefined() || root["shown_references"].IsNull()) return {};
    const std::vector<std::string> names = nameList(root["shown_references"], "shown_references");
    requireConditions(root["shown_references"], "shown_references", names, conditions);
    return names;
  }

  void requireConditions(const YAML::Node& node, const std::string& key, const std::vector<std::string>& names,
                         const std::vector<std::string>& conditions) const {
    for (const std::string& name : names) {
      if (!contains(conditions, name)) {
        fail(node, key, "'" + name + "' is not one of the plan's conditions (" + joined(conditions) + ")");
      }
    }
  }

  template <class Item, class Name>
  void requireUnique(const YAML::Node& node, const std::string& key, const std::vector<Item>& items, Name name) const {
    std::set<std::string> seen;
    for (const Item& item : items) {
      if (!seen.insert(name(item)).second) fail(node, key, "'" + name(item) + "' appears twice");
    }
  }

  // Every room must have what every condition of the plan renders from.
  void checkRoomsServeConditions(const YAML::Node& root, const MushraPlan& plan) const {
    for (std::size_t i = 0; i < plan.rooms.size(); ++i) {
      const MushraRoom& r = plan.rooms[i];
      const YAML::Node node = root["rooms"][i];
      const std::string key = "rooms[" + std::to_string(i) + "] (" + r.name + ")";
      for (const std::string& condition : kNeedRir) {
        if (plan.uses(condition) && r.bformat_rir.empty()) {
          fail(node, key + ".bformat_rir", "missing: condition " + condition + " renders from the measured B-format RIR");
        }
      }
      for (const std::string& condition : kNeedModel) {
        if (!plan.uses(condition)) continue;
        if (r.room_model.empty()) fail(node, key + ".room", "missing: condition " + condition + " simulates a room model");
        if (!r.source_m) fail(node, key + ".source_m", "missing: condition " + condition + " needs the source position");
        if (!r.listener_m) {
          fail(node, key + ".listener_m", "missing: condition " + condition + " needs the listener position");
        }
      }
      for (const MushraAttribute& a : plan.attributes) {
        if (a.show_panorama && r.panorama.empty()) {
          fail(node, key + ".panorama",
               "missing: attribute " + a.id + " shows the room's panorama (give one, or set show_panorama: false)");
        }
      }
    }
  }

  void resolveWrongRooms(const YAML::Node& root, MushraPlan& plan) const {
    const bool used = plan.uses("wrong_room");
    if (used && plan.rooms.size() < 2) {
      fail(root["conditions"], "conditions",
           "wrong_room plays the reference RIR of another room of the plan, and this plan has only one room");
    }
    for (std::size_t i = 0; i < plan.rooms.size(); ++i) {
      MushraRoom& r = plan.rooms[i];
      const YAML::Node node = root["rooms"][i];
      const std::string key = "rooms[" + std::to_string(i) + "] (" + r.name + ").wrong_room_of";
      if (!r.wrong_room_of.empty()) {
        const auto other = std::find_if(plan.rooms.begin(), plan.rooms.end(),
                                        [&](const MushraRoom& o) { return o.name == r.wrong_room_of; });
        if (other == plan.rooms.end()) fail(node["wrong_room_of"], key, "unknown room '" + r.wrong_room_of + "'");
        if (other->name == r.name) fail(node["wrong_room_of"], key, "must name another room, not the room itself");
        if (other->bformat_rir.empty()) {
          fail(node["wrong_room_of"], key, "room '" + other->name + "' has no bformat_rir to play as the wrong room");
        }
        continue;
      }
      if (!used) continue;
      // By default the next room in the plan's order (wrapping round) that has a RIR.
      for (std::size_t step = 1; step < plan.rooms.size() && r.wrong_room_of.empty(); ++step) {
        const MushraRoom& other = plan.rooms[(i + step) % plan.rooms.size()];
        if (!other.bformat_rir.empty()) r.wrong_room_of = other.name;
      }
      if (r.wrong_room_of.empty()) {
        fail(node, key, "no other room of the plan has a bformat_rir to play as this room's wrong room");
      }
    }
  }

  std::string base_;
};

}  // namespace

const std::vector<std::string>& mushraConditionNames() {
  static const std::vector<std::string> names = {"reference", "rsao", "fast", "accurate", "wrong_room", "lowpass_3k5"};
  return names;
}

bool MushraPlan::uses(const std::string& condition) const { return contains(conditions, condition); }

const MushraRoom& MushraPlan::room(const std::string& name) const {
  for (const MushraRoom& r : rooms) {
    if (r.name == name) return r;
  }
  throw InputError(source + ": unknown room '" + name + "'");
}

MushraPlan parseMushraPlan(const std::string& yaml_text, const std::string& base_directory, const std::string& source) {
  return MushraPlanReader(source, base_directory).parse(yaml_text);
}

MushraPlan loadMushraPlan(const std::string& path) {
  const std::string text = readTextFile(path, "MUSHRA plan");
  const std::filesystem::path base = std::filesystem::absolute(path).parent_path();
  return parseMushraPlan(text, base.string(), path);
}

}  // namespace room_reverb::core
