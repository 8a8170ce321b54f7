#include "room_reverb/listening/mushra_webmushra.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>

#include "room_reverb/listening/mushra_test_files.h"

namespace room_reverb::core {
namespace {

// The condition webMUSHRA gets as its labelled (and automatically hidden) reference.
std::string webMushraReference(const MushraPlan& plan) {
  if (!plan.shown_references.empty()) return plan.shown_references.front();
  if (plan.uses("reference")) return "reference";
  return plan.conditions.front();
}

// HTML for the page's text: webMUSHRA shows `content` as HTML above the sliders.
std::string escapedHtml(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

}  // namespace

std::string webMushraConfigYaml(const MushraPlan& plan, const std::vector<MushraPage>& pages,
                                const std::string& folder_name) {
  const std::string prefix = "configs/" + folder_name + "/";
  const std::string reference = webMushraReference(plan);
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "testname" << YAML::Value << "room_reverb MUSHRA test " + folder_name;
  out << YAML::Key << "testId" << YAML::Value << folder_name;
  out << YAML::Key << "bufferSize" << YAML::Value << 2048;
  out << YAML::Key << "stopOnErrors" << YAML::Value << true;
  out << YAML::Key << "showButtonPreviousPage" << YAML::Value << false;
  out << YAML::Key << "remoteService" << YAML::Value << "service/write.php";
  out << YAML::Key << "pages" << YAML::Value << YAML::BeginSeq;
  // One random group: webMUSHRA shows its pages in a new order to every listener.
  out << YAML::BeginSeq << "random";
  for (const MushraPage& page : pages) {
    std::string id = page.id;
    std::replace(id.begin(), id.end(), '/', '-');
    std::string content = escapedHtml(page.question);
    const std::string panorama = page.show_panorama ? mushraPanoramaFile(plan.room(page.room)) : "";
    if (!panorama.empty()) content += "<br/><img src=\"" + prefix + panorama + "\" style=\"max-width:100%\"/>";
    out << YAML::BeginMap;
    out << YAML::Key << "type" << YAML::Value << "mushra";
    out << YAML::Key << "id" << YAML::Value << id;
    out << YAML::Key << "name" << YAML::Value << page.room + " / " + page.content + " / " + page.attribute;
    out << YAML::Key << "content" << YAML::Value << content;
    out << YAML::Key << "showWaveform" << YAML::Value << true;
    out << YAML::Key << "enableLooping" << YAML::Value << true;
    out << YAML::Key << "reference" << YAML::Value << prefix + mushraStimulusFile(page.room, page.content, reference);
    out << YAML::Key << "createAnchor35" << YAML::Value << false;
    out << YAML::Key << "createAnchor70" << YAML::Value << false;
    out << YAML::Key << "stimuli" << YAML::Value << YAML::BeginMap;
    for (const std::string& condition : plan.conditions) {
      if (condition == reference) continue;  // webMUSHRA adds the reference as a hidden condition itself
      out << YAML::Key << condition << YAML::Value << prefix + mushraStimulusFile(page.room, page.content, condition);
    }
    out << YAML::EndMap << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::BeginMap << YAML::Key << "type" << YAML::Value << "finish" << YAML::Key << "name" << YAML::Value
      << "Thank you" << YAML::Key << "content" << YAML::Value << "Thank you for taking part." << YAML::Key
      << "showResults" << YAML::Value << false << YAML::Key << "writeResults" << YAML::Value << true << YAML::EndMap;
  out << YAML::EndSeq << YAML::EndMap;

  std::string header =
      "# webMUSHRA configuration of this test, written by room_reverb mushra make.\n"
      "# Copy this folder into webMUSHRA's configs/ folder and open index.html?config=" +
      folder_name + "/webmushra.yaml.\n# webMUSHRA's hidden condition \"reference\" is this test's condition \"" +
      reference + "\"; the other stimuli are keyed by condition name.\n";
  if (plan.scale == MushraScale::kZeroToFive) {
    header += "# The plan rates on 0-5; webMUSHRA rates on 0-100 (divide by 20 to compare).\n";
  }
  return header + out.c_str() + "\n";
}

}  // namespace room_reverb::core
