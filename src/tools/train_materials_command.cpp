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
#include "room_reverb/synthetic_capture/photo_textures.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;

const char* kHelp = R"(usage: room_reverb train-materials --out FILE.yml.gz [--samples N] [--seed S]
                                   [--max-rooms N] [--trees N] [--threads N]
                                   [--textures CSV|none] [--photo-share X]
                                   [--held-out-source NAME[,NAME...]]

Trains the material classifier of the visual route (a random forest over colour and
texture features of rectified surface patches; include/room_reverb/synthetic_capture/
material_training.h): renders random rooms with the capture generator, their materials
painted with photographs of real surfaces or drawn, cuts their surfaces into patches
labelled with the texture family of their material, trains, and reports the accuracy on
a held-out set of rooms from other seeds and on rooms painted with photographs from
collections it was not trained on (with the confusion matrix).

  --out FILE        where to write the classifier (.yml or .yml.gz, OpenCV FileStorage)
  --samples N       patches per texture family; default 800
  --seed S          seed of the random rooms (the held-out rooms use a seed derived from
                    it); default 1
  --max-rooms N     stop after this many rooms even if a family is short; default 1000
  --trees N         trees in the forest; default 80
  --threads N       worker threads (0: all cores); default 0
  --textures CSV    photographs of real surfaces (file,family,width_m,source,licence,
                    origin); default data/textures/textures.csv; none: drawn only
  --photo-share X   chance that a material is painted with a photograph when its family
                    has any, 0..1; default 0.5
  --held-out-source NAMES
                    collections (the CSV's source column) kept out of training and
                    evaluated on; default none

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
  for (const auto& [source, accuracy] : result.held_out_sources) {
    os << "\nOn photographs of a collection not trained on (" << source << "): " << percent(accuracy.overall()) << ".";
  }
  return os.str();
}


// Accuracy per family and the confusion matrix (rows: truth, columns: predicted), only
// over the families that have samples.
void printAccuracy(const std::string& title, const MaterialAccuracy& accuracy) {
  std::cout << title << ": " << percent(accuracy.overall()) << "\n";
  const std::vector<TextureFamily> all = allTextureFamilies();
  std::cout << "  " << std::left << std::setw(10) << "truth" << std::right << std::setw(9) << "right";
  for (const TextureFamily family : all) std::cout << std::setw(9) << toString(family).substr(0, 8);
  std::cout << "\n";
  for (std::size_t k = 0; k < all.size(); ++k) {
    if (accuracy.total[k] == 0) continue;
    std::cout << "  " << std::left << std::setw(10) << toString(all[k]) << std::right << std::setw(9) << percent(accuracy.of(all[k]));
    for (std::size_t j = 0; j < all.size(); ++j) std::cout << std::setw(9) << accuracy.confusion[k][j];
    std::cout << "\n";
  }
}

int runTrainMaterials(const std::vector<std::string>& raw) {
  const Arguments args(raw, {"out", "samples", "seed", "max-rooms", "trees", "threads", "textures", "photo-share", "held-out-source"}, {});
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

  const std::string textures = args.value("textures", defaultPhotoTexturePath());
  if (textures != "none") options.photo_textures = std::make_shared<const PhotoTextureSet>(loadPhotoTextures(textures));
  options.photo_share = args.doubleValue("photo-share", options.photo_share);
  if (!(options.photo_share >= 0.0 && options.photo_share <= 1.0)) throw UsageError("--photo-share needs a number in 0..1");
  if (args.has("held-out-source")) {
    if (!options.photo_textures) throw UsageError("--held-out-source needs photographs (--textures CSV)");
    options.held_out_sources = commaSeparated(args.value("held-out-source", ""));
    if (options.held_out_sources.empty()) throw UsageError("--held-out-source needs collection names separated by commas");
  }

  const MaterialTrainingResult result = trainMaterialClassifier(options, MaterialLibrary::loadDefault());
  result.classifier.save(out, description(options, result));
  std::cout << "trained on " << result.training_samples << " patches of " << result.training_rooms << " rooms in "
            << std::fixed << std::setprecision(0) << result.seconds << " s\n";
  printAccuracy("held-out rooms (other seeds)", result.held_out);
  for (const auto& [source, accuracy] : result.held_out_sources) {
    printAccuracy("photographs of " + source + " (a collection not trained on)", accuracy);
  }
  std::cout << "wrote " << out << " (" << std::filesystem::file_size(out) / 1024 << " KiB)\n";
  return 0;
}

const CommandRegistration registration({"train-materials", "train the visual route's surface-material classifier",
                                        kHelp, runTrainMaterials});

}  // namespace
}  // namespace room_reverb::tool
