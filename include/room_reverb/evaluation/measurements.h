#pragma once
// measurements.yaml (DESIGN.md): source-receiver pairs in the room frame, with or without
// their measured RIR files, and/or a table of measured room-acoustic parameters averaged
// over the pairs; optionally the room they were measured in (a room model or a mesh) and
// the air conditions during the measurement, so a simulation can be set up from the file
// alone. Paths inside the file are relative to the file.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/acoustics/air_absorption.h"
#include "room_reverb/acoustics/triangle_mesh.h"
#include "room_reverb/audio/frequency_bands.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"

namespace room_reverb::core {

struct MeasurementPair {
  std::string label;                   // e.g. "LS01-MP03"; "" when not given
  std::string file;                    // absolute path of the RIR; "" when only positions are known
  std::string format;                  // omni | fuma | ambix ("" without a file)
  Eigen::Vector3d source_m = Eigen::Vector3d::Zero();    // room frame
  Eigen::Vector3d receiver_m = Eigen::Vector3d::Zero();  // room frame
};

// A pair whose file is first-order B-format (fuma or ambix).
bool isBFormat(const MeasurementPair& pair);

// Measured parameters per band, averaged over the pairs. A missing parameter is an empty
// vector; a present one has a value per band. D50 is a fraction (a file may give percent
// with `d50_percent`).
struct MeasuredParameters {
  BandResolution resolution = BandResolution::kOctave;
  std::vector<double> bands_hz;  // nominal centres
  std::vector<double> t20_s, t30_s, edt_s, c50_db, c80_db, d50, ts_s, drr_db;
  bool empty() const { return bands_hz.empty(); }
};

// One measured RIR's parameters as a table (its bands, NaN where a value could not be
// measured), so a single pair compares like an averaged table.
MeasuredParameters parametersFromReport(const MetricsReport& report);

struct Measurements {
  std::string room_file;  // absolute path of a room.yaml, or ""
  std::string mesh_file;  // absolute path of a mesh, or ""
  UpAxis mesh_up_axis = UpAxis::kZ;
  std::optional<AirConditions> air;
  std::vector<MeasurementPair> pairs;
  MeasuredParameters parameters;
};

// Throws InputError naming the key at fault (missing pairs and parameters, a vector that
// is not three numbers, a table row whose length differs from bands_hz, unknown format).
Measurements loadMeasurements(const std::string& path);
Measurements parseMeasurements(const std::string& yaml_text, const std::string& base_directory);

}  // namespace room_reverb::core
