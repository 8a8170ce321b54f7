#include "room_reverb/listening/mushra_test_files.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "room_reverb/audio/audio_file.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/listening/mushra_page.h"
#include "room_reverb/listening/mushra_webmushra.h"

namespace room_reverb::core {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

json scaleJson(MushraScale scale) {
  const int top = scale == MushraScale::kZeroToFive ? 5 : 100;
  return {{"name", toString(scale)}, {"min", 0}, {"max", top}, {"step", 1}};
}

json nullOr(const std::string& text) { return text.empty() ? json(nullptr) : json(text); }

void prepareFolder(const fs::path& dir) {
  checkMushraOutputFolder(dir.string());
  std::error_code error;
  if (fs::is_directory(dir)) {
    fs::remove_all(dir / "stimuli", error);
    fs::remove_all(dir / "panoramas", error);
    fs::remove_all(dir / "audio", error);
  }
  createFolder(dir.string());
}

}  // namespace

// A test folder may be replaced; any other folder with files in it is the user's.
void checkMushraOutputFolder(const std::string& dir) {
  const fs::path path(dir);
  if (fs::exists(path) && !fs::is_directory(path)) throw InputError(dir + ": is a file, not a folder");
  if (fs::is_directory(path) && !fs::is_empty(path) && !fs::exists(path / "test.json")) {
    throw InputError(dir + ": the folder is not empty and holds no MUSHRA test; choose a new folder");
  }
}

std::string mushraStimulusFile(const std::string& room, const std::string& content, const std::string& condition) {
  return "stimuli/" + room + "/" + content + "/" + condition + ".wav";
}

std::string mushraPanoramaFile(const MushraRoom& room) {
  if (room.panorama.empty()) return "";
  return "panoramas/" + room.name + fs::path(room.panorama).extension().string();
}

std::string mushraTestJson(const MushraPlan& plan, const MushraStimuli& stimuli, const std::vector<MushraPage>& pages) {
  json attributes = json::array(), rooms = json::array(), contents = json::array(), page_list = json::array();
  for (const MushraAttribute& a : plan.attributes) {
    attributes.push_back({{"id", a.id}, {"question", a.question}, {"show_panorama", a.show_panorama}});
  }
  for (const MushraRoom& r : plan.rooms) rooms.push_back({{"name", r.name}, {"panorama", nullOr(mushraPanoramaFile(r))}});
  for (std::size_t c = 0; c < plan.contents.size(); ++c) {
    contents.push_back({{"name", plan.contents[c].name}, {"duration_s", stimuli.content_duration_s.at(c)}});
  }
  for (const MushraPage& page : pages) {
    json page_stimuli = json::array();
    double duration_s = 0.0;
    for (const MushraPageStimulus& s : page.stimuli) {
      const MushraStimulus& audio = stimuli.find(page.room, page.content, s.condition);
      duration_s = audio.audio.durationS();
      page_stimuli.push_back({{"letter", s.letter},
                              {"condition", s.condition},
                              {"file", mushraStimulusFile(page.room, page.content, s.condition)},
                              {"audio_script", mushraAudioScriptFile(page.room, page.content, s.condition)},
                              {"is_hidden_anchor", s.is_hidden_anchor},
                              {"is_shown_reference", s.is_shown_reference},
                              {"loudness_lufs", audio.loudness_lufs},
                              {"peak_dbfs", audio.peak_dbfs}});
    }
    page_list.push_back({{"id", page.id},
                         {"room", page.room},
                         {"content", page.content},
                         {"attribute", page.attribute},
                         {"question", page.question},
                         {"panorama", page.show_panorama ? nullOr(mushraPanoramaFile(plan.room(page.room))) : json(nullptr)},
                         {"duration_s", duration_s},
                         {"stimuli", page_stimuli}});
  }
  const json test = {{"format", "room_reverb MUSHRA test"},
                     {"version", 1},
                     {"seed", plan.seed},
                     {"scale", scaleJson(plan.scale)},
                     {"sample_rate_hz", kInternalSampleRateHz},
                     {"loudness_lufs", stimuli.target_lufs},
                     {"max_peak_dbfs", plan.max_peak_dbfs},
                     {"fade_s", kMushraFadeS},
                     {"conditions", plan.conditions},
                     {"hidden_anchors", plan.hidden_anchors},
                     {"shown_references", plan.shown_references},
                     {"attributes", attributes},
                     {"rooms", rooms},
                     {"contents", contents},
                     {"results_columns", mushraResultColumns()},
                     {"pages", page_list}};
  return test.dump(2) + "\n";
}

void writeMushraTest(const MushraPlan& plan, const MushraStimuli& stimuli, const std::vector<MushraPage>& pages,
                     const std::string& dir) {
  const fs::path root = fs::absolute(dir).lexically_normal();
  // Everything is built in memory before the folder is touched.
  const std::string test_json = mushraTestJson(plan, stimuli, pages);
  const std::string folder_name = root.has_filename() ? root.filename().string() : root.parent_path().filename().string();
  const std::string webmushra = webMushraConfigYaml(plan, pages, folder_name);
  const std::string plan_used = mushraPlanToYaml(plan);

  prepareFolder(root);
  for (const MushraStimulus& s : stimuli.stimuli) {
    const fs::path file = root / mushraStimulusFile(s.room, s.content, s.condition);
    createFolder(file.parent_path().string());
    writeAudioFile(file.string(), s.audio, SampleEncoding::kFloat32);
  }
  for (const MushraRoom& r : plan.rooms) {
    if (r.panorama.empty()) continue;
    const fs::path target = root / mushraPanoramaFile(r);
    createFolder(target.parent_path().string());
    std::error_code error;
    fs::copy_file(r.panorama, target, fs::copy_options::overwrite_existing, error);
    if (error) throw InputError(r.panorama + ": cannot copy the panorama to " + target.string() + ": " + error.message());
  }
  writeTextFile((root / "test.json").string(), test_json);
  writeTextFile((root / "plan_used.yaml").string(), plan_used);
  writeTextFile((root / "webmushra.yaml").string(), webmushra);
  writeMushraPage(stimuli, test_json, root.string());
}

}  // namespace room_reverb::core
