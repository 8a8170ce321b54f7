// diagnosis.json and report.md of a diagnosis.
#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "room_reverb/diagnosis/diagnosis.h"
#include "room_reverb/diagnosis/material_match.h"

namespace room_reverb::core {
namespace {

double rounded(double v, int digits) {
  const double scale = std::pow(10.0, digits);
  return std::round(v * scale) / scale;
}

nlohmann::json parametersJson(const CauseParameters& p) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [key, value] : p.values) j[key] = rounded(value, 4);
  for (const auto& [key, values] : p.bands) {
    nlohmann::json row = nlohmann::json::array();
    for (double v : values) row.push_back(rounded(v, 4));
    j[key] = row;
    j["bands_hz"] = {63, 125, 250, 500, 1000, 2000, 4000, 8000, 16000};
  }
  for (const auto& [key, value] : p.text) j[key] = value;
  return j;
}

nlohmann::json seedGainsJson(const SeedGains& g) {
  nlohmann::json j;
  j["gains_jnd"] = nlohmann::json::array();
  for (double x : g.gains) j["gains_jnd"].push_back(rounded(x, 4));
  j["mean_jnd"] = rounded(g.mean_jnd, 4);
  j["standard_error_jnd"] = rounded(g.standard_error_jnd, 4);
  return j;
}

// "0.19 ± 0.02 (6 seeds)", or the base seed's gain alone when it was not measured again.
std::string gainText(double base_seed_gain, const SeedGains& g) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(2);
  if (g.gains.size() < 2) {
    os << base_seed_gain;
  } else {
    os << g.mean_jnd << " ± " << g.standard_error_jnd << " (" << g.gains.size() << " seeds)";
  }
  return os.str();
}

}  // namespace

std::string describeParameters(const CauseParameters& parameters) { return parametersJson(parameters).dump(); }

std::string diagnosisToJson(const Diagnosis& d, const std::string& extended_room_path) {
  nlohmann::json j;
  j["baseline_error_jnd"] = rounded(d.baseline_error_jnd, 4);
  j["baseline_heldout_error_jnd"] = rounded(d.baseline_heldout_jnd, 4);
  j["noise_jnd"] = rounded(d.noise_jnd, 4);
  j["heldout_over_seeds_jnd"] = nlohmann::json::array();
  for (double e : d.heldout_over_seeds) j["heldout_over_seeds_jnd"].push_back(rounded(e, 4));
  j["threshold_jnd"] = rounded(d.threshold_jnd, 4);
  j["causes"] = nlohmann::json::array();
  for (const NamedCause& c : d.causes) {
    j["causes"].push_back({{"cause", c.cause},
                           {"target", c.target.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.target)},
                           {"parameters", parametersJson(c.parameters)},
                           {"error_before_jnd", rounded(c.error_before_jnd, 4)},
                           {"error_after_jnd", rounded(c.error_after_jnd, 4)},
                           {"heldout_before_jnd", rounded(c.heldout_before_jnd, 4)},
                           {"heldout_after_jnd", rounded(c.heldout_after_jnd, 4)},
                           {"heldout_gain_jnd", rounded(c.heldoutGainJnd(), 4)},
                           {"gain_over_seeds", seedGainsJson(c.over_seeds)}});
  }
  j["hypotheses"] = nlohmann::json::array();
  for (const HypothesisTrial& t : d.trials) {
    j["hypotheses"].push_back({{"cause", t.cause}, {"fitted", t.fitted}, {"target", t.target},
                               {"heldout_gain_jnd", rounded(t.heldout_gain_jnd, 4)}, {"note", t.note}});
    if (!t.over_seeds.gains.empty()) j["hypotheses"].back()["gain_over_seeds"] = seedGainsJson(t.over_seeds);
  }
  j["measurement_flags"] = nlohmann::json::array();
  for (const MeasurementFlag& f : d.flags) {
    j["measurement_flags"].push_back({{"cause", "measurement_limits"}, {"pair", f.pair}, {"issue", f.issue}, {"detail", f.detail}});
  }
  j["error_after_jnd"] = rounded(d.after.error_jnd, 4);
  j["extended_room"] = extended_room_path;
  j["simulations"] = d.simulations;
  j["wall_time_s"] = rounded(d.wall_time_s, 2);
  return j.dump(2) + "\n";
}

std::string diagnosisToMarkdown(const Diagnosis& d, const std::string& extended_room_path,
                                const std::vector<std::string>& plots) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(2);
  os << "# Diagnosis: measured against simulated\n\n";
  os << "Error of the model as given: **" << d.baseline_error_jnd << " JND** (mean absolute error, each parameter "
     << "group weighted equally; " << d.baseline_heldout_jnd << " JND on the held-out evidence). "
     << "Over ray-tracing seeds the held-out error was";
  for (std::size_t i = 0; i < d.heldout_over_seeds.size(); ++i) os << (i == 0 ? " " : ", ") << d.heldout_over_seeds[i];
  os << " JND (noise " << d.noise_jnd << " JND: √2 times their standard deviation). A cause is named when its fit "
     << "gains more than " << d.threshold_jnd << " JND (at least the noise, 0.1 JND and 8 % of the held-out error) "
     << "on evidence the fit did not use, at the base seed and on average over the seeds with the same fitted "
     << "parameters, and the average stands clear of its own spread (three standard errors).\n\n";
  if (d.causes.empty()) {
    os << "**No cause named**: no extension of the model gained more than the threshold on held-out evidence, or "
       << "its gain did not hold at the other seeds (the table of hypotheses below).\n\n";
  } else {
    os << "## Causes, ranked\n\n| # | cause | target | parameters | error before → after (JND) | held-out gain (JND) |\n"
       << "|---:|---|---|---|---|---:|\n";
    for (std::size_t i = 0; i < d.causes.size(); ++i) {
      const NamedCause& c = d.causes[i];
      os << "| " << i + 1 << " | `" << c.cause << "` | " << (c.target.empty() ? "–" : c.target) << " | "
         << describeParameters(c.parameters) << " | " << c.error_before_jnd << " → " << c.error_after_jnd << " | "
         << gainText(c.heldoutGainJnd(), c.over_seeds) << " |\n";
    }
    os << "\n";
    for (const NamedCause& c : d.causes) {
      os << "- `" << c.cause << "`: " << causeMeaning(c.cause) << ".";
      const auto nearest = c.parameters.text.find("nearest_material");
      if (nearest != c.parameters.text.end()) {
        const double off = c.parameters.values.at("nearest_material_difference");
        os << " The fitted absorption is closest to the library's `" << nearest->second << "` (at most " << off
           << " apart, 125 Hz-8 kHz)";
        if (off > kImplausibleAbsorptionDifference) {
          os << "; **no material in the library absorbs like this** (" << off << " off at "
             << c.parameters.values.at("nearest_material_worst_band_hz")
             << " Hz): the fit may be taking up another cause's error rather than finding the surface's material";
        }
        os << ".";
      }
      os << "\n";
    }
    os << "\nError after all named causes: **" << d.after.error_jnd << " JND** (held out " << d.after.heldout_error_jnd
       << ").\n\n";
  }
  os << "## Error per parameter, before and after\n\n| parameter | before (JND) | after (JND) |\n|---|---:|---:|\n";
  const auto before = groupMeanAbsoluteErrors(d.before.terms, -1), after = groupMeanAbsoluteErrors(d.after.terms, -1);
  for (const auto& [group, value] : before) {
    os << "| " << group << " | " << value << " | " << (after.count(group) ? after.at(group) : NAN) << " |\n";
  }
  os << "\n(`early`: the early energy profile, windows of 2.5 ms after the direct sound per octave from 500 Hz, in dB "
        "re the direct sound; 1 dB counts as one JND.";
  if (before.count("reflections")) {
    os << " `reflections`: per pair, the strong measured early reflections (within 30 ms, at most 14 dB below the "
          "direct sound) that no path of the model explains and a missing surface could make, each counted by its "
          "level above -14 dB.";
  }
  os << ")\n\n";
  os << "## Every hypothesis tried (first round)\n\n| cause | fitted | target | held-out gain (JND) | fit or why not |\n"
     << "|---|---|---|---:|---|\n";
  for (const HypothesisTrial& t : d.trials) {
    os << "| `" << t.cause << "` | " << (t.fitted ? "yes" : "no") << " | " << (t.target.empty() ? "–" : t.target) << " | "
       << gainText(t.heldout_gain_jnd, t.over_seeds) << " | " << t.note << " |\n";
  }
  if (!d.flags.empty()) {
    os << "\n## Limits of the measurement (`measurement_limits`: the measurement's, not the model's)\n\n";
    for (const MeasurementFlag& f : d.flags) os << "- " << f.pair << ": **" << f.issue << "**: " << f.detail << "\n";
  }
  if (!plots.empty()) {
    os << "\n## Figures\n\n";
    for (const std::string& p : plots) os << "![" << p << "](" << p << ")\n\n";
  }
  if (!extended_room_path.empty()) {
    os << "\nCorrected room model: `" << extended_room_path << "`.";
    std::vector<std::string> outside;
    if (d.extension.directivity) outside.push_back("the source's directivity");
    if (d.extension.coupled) outside.push_back("the coupled decay");
    if (d.extension.modes) outside.push_back("the modal low band");
    if (d.extension.diffraction_scattering) outside.push_back("the diffraction scattering (`--diffraction-scattering`)");
    if (d.extension.wave_low_band) outside.push_back("the wave low band (`--low-band wave`)");
    if (d.extension.third_octave_bands) outside.push_back("the third-octave bands (`--bands third`)");
    for (std::size_t i = 0; i < outside.size(); ++i) {
      os << (i == 0 ? " The room format cannot hold " : i + 1 == outside.size() ? " and " : ", ") << outside[i];
    }
    if (!outside.empty()) os << ": those are in `diagnosis.json` only.";
    os << "\n";
  }
  os << "\n" << d.simulations << " model simulations, " << d.wall_time_s << " s.\n";
  return os.str();
}

}  // namespace room_reverb::core
