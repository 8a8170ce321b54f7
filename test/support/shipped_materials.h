#pragma once
// The package's shipped material models, loaded once per test process: the material
// library, the surface-material classifier and the family table (config/).
#include <string>

#include "room_reverb/acoustics/material.h"
#include "room_reverb/vision/material_classifier.h"
#include "room_reverb/vision/material_families.h"

namespace room_reverb::test {

inline std::string sourcePath(const std::string& relative) { return std::string(ROOM_REVERB_SOURCE_DIR) + "/" + relative; }

inline const core::MaterialLibrary& library() {
  static const core::MaterialLibrary materials = core::MaterialLibrary::load(sourcePath("config/materials.yaml"));
  return materials;
}

inline const core::MaterialClassifier& shippedClassifier() {
  static const core::MaterialClassifier classifier = core::MaterialClassifier::load(sourcePath("config/material_classifier.yml.gz"));
  return classifier;
}

inline const core::MaterialFamilyTable& shippedFamilies() {
  static const core::MaterialFamilyTable table = core::loadMaterialFamilyTable(sourcePath("config/material_families.yaml"), library());
  return table;
}

}  // namespace room_reverb::test
