// The plan as a test used it (DIR/plan_used.yaml): the plan format with every default
// written out and every path absolute, so that the test can be made again, and so that a
// reader sees which wrong room each room was given and which HRTF set was used.
#include <yaml-cpp/yaml.h>

#include "room_reverb/listening/mushra_plan.h"

namespace room_reverb::core {
namespace {

void vector3(YAML::Emitter& out, const char* key, const std::optional<Eigen::Vector3d>& v) {
  if (!v) return;
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq << (*v)[0] << (*v)[1] << (*v)[2]
      << YAML::EndSeq;
}

void nameList(YAML::Emitter& out, const char* key, const std::vector<std::string>& names) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const std::string& name : names) out << name;
  out << YAML::EndSeq;
}

void room(YAML::Emitter& out, const MushraRoom& r) {
  out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << r.name;
  if (!r.bformat_rir.empty()) {
    out << YAML::Key << "bformat_rir" << YAML::Value << r.bformat_rir;
    out << YAML::Key << "format" << YAML::Value << toString(r.format);
  }
  if (!r.room_model.empty()) out << YAML::Key << "room" << YAML::Value << r.room_model;
  vector3(out, "source_m", r.source_m);
  vector3(out, "listener_m", r.listener_m);
  if (!r.panorama.empty()) out << YAML::Key << "panorama" << YAML::Value << r.panorama;
  if (!r.wrong_room_of.empty()) out << YAML::Key << "wrong_room_of" << YAML::Value << r.wrong_room_of;
  out << YAML::EndMap;
}

}  // namespace

std::string mushraPlanToYaml(const MushraPlan& plan) {
  YAML::Emitter out;
  out.SetDoublePrecision(9);
  out << YAML::BeginMap;
  out << YAML::Key << "seed" << YAML::Value << plan.seed;
  out << YAML::Key << "scale" << YAML::Value << toString(plan.scale);
  if (plan.duration_s) out << YAML::Key << "duration_s" << YAML::Value << *plan.duration_s;
  out << YAML::Key << "loudness_lufs" << YAML::Value << plan.loudness_lufs;
  out << YAML::Key << "max_peak_dbfs" << YAML::Value << plan.max_peak_dbfs;
  out << YAML::Key << "hrtf" << YAML::Value << plan.hrtf;
  out << YAML::Key << "decoder" << YAML::Value << toString(plan.decoder);
  const MushraSimulation& s = plan.simulation;
  out << YAML::Key << "simulation" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "rays"
      << YAML::Value << s.rays << YAML::Key << "image_source_order" << YAML::Value << s.image_source_order
      << YAML::Key << "ambisonic_order" << YAML::Value << s.ambisonic_order << YAML::Key << "duration_s"
      << YAML::Value << s.duration_s << YAML::Key << "threads" << YAML::Value << s.threads << YAML::EndMap;
  out << YAML::Key << "rooms" << YAML::Value << YAML::BeginSeq;
  for (const MushraRoom& r : plan.rooms) room(out, r);
  out << YAML::EndSeq;
  out << YAML::Key << "contents" << YAML::Value << YAML::BeginSeq;
  for (const MushraContent& c : plan.contents) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << c.name << YAML::Key << "file"
        << YAML::Value << c.file << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "attributes" << YAML::Value << YAML::BeginSeq;
  for (const MushraAttribute& a : plan.attributes) {
    out << YAML::BeginMap << YAML::Key << "id" << YAML::Value << a.id << YAML::Key << "question" << YAML::Value
        << a.question << YAML::Key << "show_panorama" << YAML::Value << a.show_panorama << YAML::EndMap;
  }
  out << YAML::EndSeq;
  nameList(out, "conditions", plan.conditions);
  nameList(out, "hidden_anchors", plan.hidden_anchors);
  nameList(out, "shown_references", plan.shown_references);
  out << YAML::EndMap;
  return std::string("# The plan as `room_reverb mushra make` used it: defaults filled in, paths absolute.\n") +
         out.c_str() + "\n";
}

}  // namespace room_reverb::core
