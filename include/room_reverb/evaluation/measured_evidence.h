#pragma once
// What a measurement tells about a room, in the form the comparison and the diagnosis use:
// per measured RIR its ISO 3382 parameters (omni channel), its early energy profile, its
// RSAO and the directions of its early energy (B-format files) and the limits of the
// measurement itself; or the averaged table of a measurement without files.
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/audio/audio_buffer.h"
#include "room_reverb/evaluation/early_direction.h"
#include "room_reverb/evaluation/early_energy.h"
#include "room_reverb/evaluation/measurements.h"
#include "room_reverb/evaluation/reflection_matching.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"
#include "room_reverb/rsao/rsao.h"

namespace room_reverb::core {

// A limit of the measurement, not of the model (the catalogue's `measurement_limits`).
struct MeasurementFlag {
  std::string pair;    // the pair's label or file
  std::string issue;   // clipping | noise_floor | bformat_convention
  std::string detail;  // a sentence for the report
};

struct PairEvidence {
  MeasurementPair pair;
  std::vector<float> omni;   // 48 kHz omni (W) channel
  MetricsReport metrics;     // octave bands
  EarlyEnergyProfile early;
  // B-format files: where the early reflections come from (early_direction.h).
  std::optional<EarlyDirectionProfile> directions;
  std::optional<Rsao> rsao;  // B-format files with a clear direct sound only
  // B-format files with a clear direct sound: the reflections the diagnosis's reflection
  // term sets against the model's specular paths (reflection_evidence.h).
  std::optional<std::vector<RelativeReflection>> reflections;
};

struct MeasuredEvidence {
  std::vector<MeasurementPair> positions;  // every pair to simulate, with or without a file
  std::vector<PairEvidence> rirs;          // pairs with a file, in the order of `positions`
  MeasuredParameters table;                // averaged table (may be empty)
  std::vector<MeasurementFlag> flags;
  bool usesRirs() const { return !rirs.empty(); }
};

// Reads and analyses every pair's file. InputError (naming the file) for a missing or
// unreadable file, a channel count that does not fit its format (omni: 1; fuma/ambix: 4),
// a sample rate below 16 kHz (the 8 kHz band would be lost), silence or NaN; files at
// other rates are resampled to 48 kHz. Either every pair has a file or none has; a
// measurement with neither files nor a table is an error.
MeasuredEvidence measuredEvidence(const Measurements& measurements);

// The analysis one response gets, measured or simulated alike (omni channel 0 of a 48 kHz
// buffer; the RSAO and the reflection evidence when `bformat_ambix` has four channels).
PairEvidence analysePair(const MeasurementPair& pair, const AudioBuffer& ambix_or_omni);

}  // namespace room_reverb::core
