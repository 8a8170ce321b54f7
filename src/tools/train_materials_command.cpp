// room_reverb train-materials: trains the surface-material classifier of the visual route
// on the capture generator's textures and writes it (config/material_classifier.yml.gz
// is made this way; see scripts/train-material-classifier).
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "arguments.h"
#include "command.h"
#include "room_reverb/acoustics/material.h"
#include "room_reverb/common/error.h"
#include "room_reverb/synthetic_capture/material_training.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelp = R"(usage: room_reverb train-materials --out FILE.yml.gz [--samples N] [--seed S]
                                   [--max-rooms N] [--trees N] [--threads N]

Trains the material classifier of the visual route (a random forest over colour and
texture features of rectified surface patches; include/room_reverb/vision/
material_training.h): renders random rooms with the capture generator, cuts their
surfaces into patches labelled with the texture family of their material, trains, and
reports the accuracy on a held-out set of rooms from other seeds.

  --out FILE        where to write the classifier (.yml or .yml.gz, OpenCV FileStorage)
  --samples N       patches per texture family; default 800
  --seed S          seed of the random rooms (the held-out rooms use a seed derived from
                    it); default 1
  --max-rooms N     stop after this many rooms even if a family is short; default 1000
  --trees N         trees in the forest; default 80
  --threads N       worker threads (0: all cores); default 0

Exit status: 0 on success, 2 with one line on stderr for bad input.
)";

std::string percent(double fraction) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(1) << 100.0 * fraction << " %";
  return os.str();
}

// The comment at the top of the file: what it is and how to make it again.
std::string description(const MaterialTrainingOptions& options, const MaterialTrainingResult& result) {
  std::ostringstream os;
  os << "room_reverb surface-material classifier (include/room_reverb/vision/material_classifier.h).\n"
     << "A random forest (" << options.forest.trees << " trees, depth <= " << options.forest.max_depth
     << ") over the colour/texture features of include/room_reverb/vision/material_features.h,\n"
     << "on " << options.geometry.size_m << " m rectified surface patches of " << options.geometry.pixels << " x "
     << options.geometry.pixels << " pixels; classes: the texture families of texture_family.h.\n"
     << "Trained by: room_reverb train-materials --samples " << options.patches_per_family << " --seed " << options.seed
     << " --trees " << options.forest.trees << " (scripts/train-material-classifier),\n"
     << "on " << result.training_samples << " patches of " << result.training_rooms
     << " random rooms rendered by the capture generator (not the scenes of data/captures).\n"
     << "Held-out accuracy (other rooms, other seeds): " << percent(result.held_out.overall()) << ".";
  return os.str();
}

int runTrainMaterials(const std::vector<std::string>& raw) {
  const Arguments args(raw, {"out", "samples", "seed", "max-rooms", "trees", "threads"}, {});
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional().front() + "'");
  if (!args.has("out")) throw UsageError("--out FILE.yml.gz is required");
  MaterialTrainingOptions options;
  options.patches_per_family = args.intValue("samples", options.patches_per_family);
  options.max_rooms = args.intValue("max-rooms", options.max_rooms);
  options.forest.trees = args.intValue("trees", options.forest.trees);
  options.threads = args.intValue("threads", options.threads);
  const int seed = args.intValue("seed", 1);
  if (seed < 0) throw UsageError("--seed needs a whole number >= 0");
  options.seed = static_cast<std::uint64_t>(seed);
  if (options.forest.trees < 1) throw UsageError("--trees needs at least 1");
  const std::string out = args.value("out", "");
  const std::filesystem::path folder = std::filesystem::path(out).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder)) throw InputError(out + ": the folder does not exist");

  const MaterialTrainingResult result = trainMaterialClassifier(options, MaterialLibrary::loadDefault());
  result.classifier.save(out, description(options, result));
  std::cout << "trained on " << result.training_samples << " patches of " << result.training_rooms << " rooms in "
            << std::fixed << std::setprecision(0) << result.seconds << " s; held-out accuracy "
            << percent(result.held_out.overall()) << "\n";
  for (const TextureFamily family : allTextureFamilies()) {
    std::cout << "  " << std::left << std::setw(10) << toString(family) << " " << percent(result.held_out.of(family)) << "\n";
  }
  std::cout << "wrote " << out << " (" << std::filesystem::file_size(out) / 1024 << " KiB)\n";
  return 0;
}

const CommandRegistration registration({"train-materials", "train the visual route's surface-material classifier",
                                        kHelp, runTrainMaterials});

}  // namespace
}  // namespace room_reverb::tool
