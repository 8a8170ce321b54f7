#include "room_reverb/diagnosis/diagnosis_output.h"

#include <filesystem>

#include "room_reverb/acoustics/room_model.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/diagnosis/diagnosis_plots.h"

namespace room_reverb::core {

DiagnosisFiles writeDiagnosis(const Diagnosis& diagnosis, const RoomUnderTest& room, const MeasuredEvidence& evidence,
                              const std::string& directory) {
  namespace fs = std::filesystem;
  createFolder(directory);
  DiagnosisFiles files;
  const fs::path dir(directory);
  if (room.isRoomModel()) {
    files.extended_room = (dir / "extended_room.yaml").string();
    saveRoomModel(files.extended_room, room.extendedRoomModel(diagnosis.extension));
  }
  files.plots = writeDiagnosisPlots(diagnosis, evidence, directory);
  files.json = (dir / "diagnosis.json").string();
  writeTextFile(files.json, diagnosisToJson(diagnosis, files.extended_room));
  std::vector<std::string> plot_names;
  for (const std::string& p : files.plots) plot_names.push_back(fs::path(p).filename().string());
  files.report = (dir / "report.md").string();
  writeTextFile(files.report, diagnosisToMarkdown(diagnosis, files.extended_room, plot_names));
  return files;
}

}  // namespace room_reverb::core
