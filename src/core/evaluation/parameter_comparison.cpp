#include "room_reverb/evaluation/parameter_comparison.h"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace room_reverb::core {
namespace {

std::size_t indexOf(ComparedParameter p) { return static_cast<std::size_t>(p); }

const std::vector<double>& measuredRow(const MeasuredParameters& m, ComparedParameter p) {
  switch (p) {
    case ComparedParameter::kT20: return m.t20_s;
    case ComparedParameter::kT30: return m.t30_s;
    case ComparedParameter::kEdt: return m.edt_s;
    case ComparedParameter::kC50: return m.c50_db;
    case ComparedParameter::kC80: return m.c80_db;
    case ComparedParameter::kD50: return m.d50;
    case ComparedParameter::kTs: return m.ts_s;
    case ComparedParameter::kDrr: return m.drr_db;
  }
  return m.t20_s;
}

bool isDecayTime(ComparedParameter p) {
  return p == ComparedParameter::kT20 || p == ComparedParameter::kT30 || p == ComparedParameter::kEdt;
}

int thirdCount(const std::vector<BandComparison>& thirds, const FrequencyBand& octave) {
  int n = 0;
  for (const BandComparison& t : thirds) n += (t.nominal_hz >= octave.lower_hz && t.nominal_hz < octave.upper_hz) ? 1 : 0;
  return n;
}

bool sameBand(double a_hz, double b_hz) { return std::abs(std::log2(a_hz / b_hz)) < 1.0 / 6.0; }

void setErrors(BandComparison& row) {
  for (ComparedParameter p : kComparedParameters) {
    const std::size_t i = indexOf(p);
    row.error_jnd[i].reset();
    if (row.simulated[i] && row.measured[i]) row.error_jnd[i] = errorInJnd(p, *row.simulated[i], *row.measured[i]);
  }
}

}  // namespace

std::string toString(ComparedParameter parameter) {
  switch (parameter) {
    case ComparedParameter::kT20: return "T20";
    case ComparedParameter::kT30: return "T30";
    case ComparedParameter::kEdt: return "EDT";
    case ComparedParameter::kC50: return "C50";
    case ComparedParameter::kC80: return "C80";
    case ComparedParameter::kD50: return "D50";
    case ComparedParameter::kTs: return "Ts";
    case ComparedParameter::kDrr: return "DRR";
  }
  return "?";
}

std::string unitOf(ComparedParameter parameter) {
  if (parameter == ComparedParameter::kD50) return "";
  if (isDecayTime(parameter) || parameter == ComparedParameter::kTs) return "s";
  return "dB";
}

std::optional<double> parameterValue(const AcousticParameters& band, ComparedParameter parameter) {
  switch (parameter) {
    case ComparedParameter::kT20: return band.t20_s;
    case ComparedParameter::kT30: return band.t30_s;
    case ComparedParameter::kEdt: return band.edt_s;
    case ComparedParameter::kC50: return band.c50_db;
    case ComparedParameter::kC80: return band.c80_db;
    case ComparedParameter::kD50: return band.d50;
    case ComparedParameter::kTs: return band.ts_s;
    case ComparedParameter::kDrr: return band.drr_db;
  }
  return std::nullopt;
}

double justNoticeableDifference(ComparedParameter parameter) {
  switch (parameter) {
    case ComparedParameter::kT20:
    case ComparedParameter::kT30:
    case ComparedParameter::kEdt: return 0.05;  // relative
    case ComparedParameter::kC50:
    case ComparedParameter::kC80: return 1.0;   // dB
    case ComparedParameter::kD50: return 0.05;  // absolute fraction
    case ComparedParameter::kTs: return 0.010;  // s
    case ComparedParameter::kDrr: return 1.0;   // dB
  }
  return 1.0;
}

double errorInJnd(ComparedParameter parameter, double simulated, double measured) {
  const double jnd = justNoticeableDifference(parameter);
  if (isDecayTime(parameter)) return (simulated - measured) / measured / jnd;
  return (simulated - measured) / jnd;
}

std::vector<BandComparison> compareWithMeasured(const std::vector<MetricsReport>& simulated_per_pair,
                                                const MeasuredParameters& measured) {
  std::vector<BandComparison> rows;
  for (std::size_t m = 0; m < measured.bands_hz.size(); ++m) {
    BandComparison row;
    row.nominal_hz = measured.bands_hz[m];
    for (ComparedParameter p : kComparedParameters) {
      const std::vector<double>& values = measuredRow(measured, p);
      if (!values.empty() && std::isfinite(values[m])) row.measured[indexOf(p)] = values[m];
      double sum = 0.0;
      int count = 0;
      for (const MetricsReport& report : simulated_per_pair) {
        for (const AcousticParameters& band : report.bands) {
          if (!sameBand(band.nominal_hz, row.nominal_hz)) continue;
          if (const auto v = parameterValue(band, p)) {
            sum += *v;
            ++count;
          }
        }
      }
      if (count > 0) row.simulated[indexOf(p)] = sum / count;
      if (p == ComparedParameter::kT20) row.simulated_count = count;
    }
    setErrors(row);
    rows.push_back(row);
  }
  return rows;
}

std::vector<BandComparison> averageComparisons(const std::vector<std::vector<BandComparison>>& per_pair) {
  std::vector<BandComparison> rows;
  if (per_pair.empty()) return rows;
  for (std::size_t b = 0; b < per_pair.front().size(); ++b) {
    BandComparison row;
    row.nominal_hz = per_pair.front()[b].nominal_hz;
    for (ComparedParameter p : kComparedParameters) {
      const std::size_t i = indexOf(p);
      double sim = 0.0, meas = 0.0;
      int n = 0;
      for (const auto& pair : per_pair) {
        if (b >= pair.size() || !sameBand(pair[b].nominal_hz, row.nominal_hz)) continue;
        if (!pair[b].simulated[i] || !pair[b].measured[i]) continue;
        sim += *pair[b].simulated[i];
        meas += *pair[b].measured[i];
        ++n;
      }
      if (n == 0) continue;
      row.simulated[i] = sim / n;
      row.measured[i] = meas / n;
      if (p == ComparedParameter::kT20) row.simulated_count = n;
    }
    setErrors(row);
    rows.push_back(row);
  }
  return rows;
}

std::vector<BandComparison> thirdsToOctaves(const std::vector<BandComparison>& thirds) {
  std::vector<BandComparison> octaves;
  for (const FrequencyBand& octave : standardBands(BandResolution::kOctave)) {
    BandComparison row;
    row.nominal_hz = octave.nominal_hz;
    bool any = false;
    for (ComparedParameter p : kComparedParameters) {
      const std::size_t i = indexOf(p);
      double sim = 0.0, meas = 0.0;
      int sim_n = 0, meas_n = 0;
      for (const BandComparison& t : thirds) {
        // A third belongs to the octave whose edges hold its centre.
        const double centre = t.nominal_hz;
        if (!(centre >= octave.lower_hz && centre < octave.upper_hz)) continue;
        any = true;
        if (t.simulated[i]) { sim += *t.simulated[i]; ++sim_n; }
        if (t.measured[i]) { meas += *t.measured[i]; ++meas_n; }
        if (p == ComparedParameter::kT20) row.simulated_count = std::max(row.simulated_count, t.simulated_count);
      }
      if (sim_n > 0) row.simulated[i] = sim / sim_n;
      if (meas_n > 0) row.measured[i] = meas / meas_n;
    }
    // An octave needs at least two of its thirds in the table to stand for it.
    if (!any || thirdCount(thirds, octave) < 2) continue;
    setErrors(row);
    octaves.push_back(row);
  }
  return octaves;
}

std::string comparisonToMarkdown(const std::vector<BandComparison>& rows) {
  std::vector<ComparedParameter> shown;
  for (ComparedParameter p : kComparedParameters) {
    for (const BandComparison& row : rows) {
      if (row.measured[indexOf(p)]) {
        shown.push_back(p);
        break;
      }
    }
  }
  std::ostringstream os;
  os << "| band Hz |";
  for (ComparedParameter p : shown) {
    const std::string unit = unitOf(p).empty() ? "" : " " + unitOf(p);
    os << " " << toString(p) << " sim" << unit << " | " << toString(p) << " meas" << unit << " | " << toString(p) << " err JND |";
  }
  os << "\n|---:|";
  for (std::size_t i = 0; i < shown.size(); ++i) os << "---:|---:|---:|";
  os << "\n";
  const auto cell = [&os](const std::optional<double>& v, int precision) {
    if (v) {
      os << " " << std::fixed << std::setprecision(precision) << *v << " |";
    } else {
      os << " – |";
    }
  };
  for (const BandComparison& row : rows) {
    os << "| " << std::fixed << std::setprecision(0) << row.nominal_hz << " |";
    for (ComparedParameter p : shown) {
      const std::size_t i = indexOf(p);
      const int precision = unitOf(p) == "dB" ? 2 : 3;
      cell(row.simulated[i], precision);
      cell(row.measured[i], precision);
      if (row.error_jnd[i]) {
        const bool within = std::abs(*row.error_jnd[i]) <= 1.0;
        os << " " << (within ? "" : "**") << std::showpos << std::fixed << std::setprecision(1) << *row.error_jnd[i]
           << std::noshowpos << (within ? "" : "**") << " |";
      } else {
        os << " – |";
      }
    }
    os << "\n";
  }
  return os.str();
}

}  // namespace room_reverb::core
