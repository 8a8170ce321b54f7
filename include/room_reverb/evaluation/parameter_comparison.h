#pragma once
// Simulated against measured room-acoustic parameters, band by band, with the error in
// just-noticeable differences (ISO 3382-1 annex A: 5 % for T20 and EDT, 1 dB for C80,
// 0.05 for D50), as the BRAS round robins report them.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/evaluation/measurements.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"

namespace room_reverb::core {

enum class ComparedParameter { kT20, kEdt, kC80, kD50 };
constexpr std::array<ComparedParameter, 4> kComparedParameters = {ComparedParameter::kT20, ComparedParameter::kEdt,
                                                                  ComparedParameter::kC80, ComparedParameter::kD50};
std::string toString(ComparedParameter parameter);  // "T20", "EDT", "C80", "D50"
double justNoticeableDifference(ComparedParameter parameter);
// Signed error in JNDs: relative for T20 and EDT, absolute for C80 and D50.
double errorInJnd(ComparedParameter parameter, double simulated, double measured);

struct BandComparison {
  double nominal_hz = 0.0;
  // Indexed by ComparedParameter; empty where not measured or not measurable.
  std::array<std::optional<double>, 4> simulated, measured, error_jnd;
  int simulated_count = 0;  // pairs whose simulated value entered the mean (per band, of T20)
};

// Means the simulated parameters over the pairs (reports at the measured table's
// resolution) and sets them against the table, band by band; bands match by nominal
// centre within a sixth of an octave (tables write 6350 for 6300 Hz, 155 for 160 Hz).
std::vector<BandComparison> compareWithMeasured(const std::vector<MetricsReport>& simulated_per_pair,
                                                const MeasuredParameters& measured);

// Third-octave rows merged into octave rows: each value the mean of the octave's
// available thirds (as measured tables are usually reduced), errors recomputed. Octaves
// with fewer than two thirds in the table are left out.
std::vector<BandComparison> thirdsToOctaves(const std::vector<BandComparison>& thirds);

// A Markdown table: one row per band, per parameter simulated | measured | error (JND).
std::string comparisonToMarkdown(const std::vector<BandComparison>& rows);

}  // namespace room_reverb::core
