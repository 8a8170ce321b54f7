#pragma once
// Simulated against measured room-acoustic parameters, band by band, with the error in
// just-noticeable differences (ISO 3382-1 annex A: 5 % for T20, T30 and EDT, 1 dB for
// C50 and C80, 0.05 for D50, 10 ms for Ts; 1 dB for the DRR), as the BRAS
// round robins report them.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/evaluation/measurements.h"
#include "room_reverb/metrics/room_acoustic_parameters.h"

namespace room_reverb::core {

enum class ComparedParameter { kT20, kT30, kEdt, kC50, kC80, kD50, kTs, kDrr };
constexpr std::size_t kComparedParameterCount = 8;
constexpr std::array<ComparedParameter, kComparedParameterCount> kComparedParameters = {
    ComparedParameter::kT20, ComparedParameter::kT30, ComparedParameter::kEdt, ComparedParameter::kC50,
    ComparedParameter::kC80, ComparedParameter::kD50, ComparedParameter::kTs,  ComparedParameter::kDrr};
std::string toString(ComparedParameter parameter);  // "T20", "T30", "EDT", "C50", "C80", "D50", "Ts", "DRR"
std::string unitOf(ComparedParameter parameter);    // "s", "dB" or "" (D50 is a fraction)
// The parameter's value in a band of a metrics report, when it could be measured.
std::optional<double> parameterValue(const AcousticParameters& band, ComparedParameter parameter);
double justNoticeableDifference(ComparedParameter parameter);
// Signed error in JNDs: relative for T20, T30 and EDT, absolute for the others.
double errorInJnd(ComparedParameter parameter, double simulated, double measured);

struct BandComparison {
  double nominal_hz = 0.0;
  // Indexed by ComparedParameter; empty where not measured or not measurable.
  std::array<std::optional<double>, kComparedParameterCount> simulated, measured, error_jnd;
  int simulated_count = 0;  // pairs whose simulated value entered the mean (per band, of T20)
};

// Means the simulated parameters over the pairs (reports at the measured table's
// resolution) and sets them against the table, band by band; bands match by nominal
// centre within a sixth of an octave (tables write 6350 for 6300 Hz, 155 for 160 Hz).
std::vector<BandComparison> compareWithMeasured(const std::vector<MetricsReport>& simulated_per_pair,
                                                const MeasuredParameters& measured);

// Per-pair comparisons (rows for the same bands) averaged: per band and parameter the
// means of simulated and of measured over the pairs that have both, errors of the means.
std::vector<BandComparison> averageComparisons(const std::vector<std::vector<BandComparison>>& per_pair);

// Third-octave rows merged into octave rows: each value the mean of the octave's
// available thirds (as measured tables are usually reduced), errors recomputed. Octaves
// with fewer than two thirds in the table are left out.
std::vector<BandComparison> thirdsToOctaves(const std::vector<BandComparison>& thirds);

// A Markdown table: one row per band, per parameter simulated | measured | error (JND);
// parameters that no row measures are left out.
std::string comparisonToMarkdown(const std::vector<BandComparison>& rows);

}  // namespace room_reverb::core
