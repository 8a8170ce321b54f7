// room_reverb mushra: MUSHRA listening tests of the project's renders, after
// Remaggi et al.'s audio-visual tests (0-5 scale, hidden reference and wrong-room anchor)
// or ITU-R BS.1534-3 (0-100). One command whose first argument names the step; `make`
// (mushra_make_command.cpp) renders a test from a plan, `serve` (mushra_serve_command.cpp)
// serves its page and collects the results, `analyze` turns results files into screening,
// descriptive statistics and paired tests.
#include <cctype>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "arguments.h"
#include "command.h"
#include "mushra_steps.h"
#include "room_reverb/common/plots.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/text_file.h"
#include "room_reverb/listening/mushra_results.h"
#include "room_reverb/listening/mushra_screening.h"
#include "room_reverb/listening/mushra_statistics.h"

namespace room_reverb::tool {
namespace {

using namespace room_reverb::core;
using nlohmann::json;

const char* kAnalyzeHelp = R"(usage: room_reverb mushra analyze RESULTS.csv [RESULTS2.csv ...] --out DIR
                       [--scale 0-5|0-100] [--pairs A:B,C:D] [--reference NAME]
                       [--low-anchors A,B] [--alpha 0.05]

analyze: the statistics of a MUSHRA test from the results files its page saves (CSV with
the columns listener,page,room,content,attribute,condition,letter,score,duration_s in any
order). Files are merged; a listener who lacks pages or ratings others have is excluded
with the reason. Then post-screening: the anchor rule of Remaggi et al. (more than two
misidentified anchors exclude a listener; a page's hidden reference must be rated highest
or equal to the highest, each low anchor lowest or equal to the lowest non-anchor), and
on the 0-100 scale also ITU-R BS.1534-3 4.1.2 (hidden reference below 90 on more than
15 % of the pages). For every attribute and condition, and per content: n, mean, median,
quartiles, standard deviation and the confidence interval of the mean (Student's t).
Paired tests per attribute between condition pairs, paired by listener and page:
Student's paired t-test with h = 1 when p < alpha (Remaggi et al., Table 2), Wilcoxon's
signed-rank test (zero differences dropped; exact for up to 25 untied differences, else
the normal approximation), and Holm-adjusted p-values over the pairs.
Writes DIR/stats.json and DIR/report.md.

  --out DIR            output folder (created if missing; required)
  --scale S            0-5 (default: integers, as in the paper) or 0-100 (BS.1534)
  --pairs A:B,...      condition pairs to test (default: every pair of conditions that
                       are neither the reference nor a low anchor)
  --reference NAME     the hidden reference's condition name (default reference)
  --low-anchors A,B    the low anchors' condition names (default wrong_room; none for none)
  --alpha A            significance level of h; the intervals are at 1 - A (default 0.05)

Exit status: 0 on success, 2 with one line on stderr for bad input.
)";

// Everything the analysis found, for the two output files.
struct Analysis {
  std::vector<std::string> files;
  MushraScale scale = MushraScale::kZeroToFive;
  double alpha = 0.05;
  ScreeningOptions screening_options;
  MushraResults results;
  ScreeningResult screening;
  std::vector<ConditionSummary> summaries;             // per attribute and condition
  std::vector<ConditionSummary> summaries_by_content;  // per attribute, content and condition
  std::vector<PairComparison> comparisons;
};

// ---- Box plots -----------------------------------------------------------------------

struct BoxPlotPanel {
  std::string attribute;
  std::string content;
  std::vector<std::pair<std::string, std::vector<double>>> boxes;  // condition and its scores
};

// The score vectors of the box plots (the paper's Figure 4): one panel per attribute and
// content, one box per condition.
std::vector<BoxPlotPanel> collectBoxPlotPanels(const std::vector<MushraRating>& kept_ratings) {
  std::vector<BoxPlotPanel> panels;
  for (ScoreGroup& group : groupScores(kept_ratings, true)) {
    if (panels.empty() || panels.back().attribute != group.attribute || panels.back().content != group.content) {
      panels.push_back({group.attribute, group.content, {}});
    }
    panels.back().boxes.emplace_back(group.condition, std::move(group.scores));
  }
  return panels;
}

// One PNG per attribute (boxplot_<attribute>.png), a panel per content, as the paper's
// Figure 4 splits speech from music.
void writeBoxPlotFiles(const std::vector<BoxPlotPanel>& panels, MushraScale scale, const std::filesystem::path& out) {
  std::map<std::string, std::vector<BoxPanel>> by_attribute;
  const double top = scale == MushraScale::kZeroToFive ? 5.0 : 100.0;
  for (const BoxPlotPanel& p : panels) {
    BoxPanel panel;
    panel.title = p.attribute + ", " + p.content;
    panel.y_label = "score";
    panel.x_label = "condition";
    panel.y_range = std::make_pair(-0.05 * top, 1.05 * top);
    for (std::size_t i = 0; i < p.boxes.size(); ++i) {
      panel.boxes.push_back({p.boxes[i].first, p.boxes[i].second, plotPalette(i)});
    }
    by_attribute[p.attribute].push_back(panel);
  }
  for (const auto& [attribute, attribute_panels] : by_attribute) {
    std::string name;
    for (char ch : attribute) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    writeBoxPlots((out / ("boxplot_" + name + ".png")).string(), attribute_panels, 2);
  }
}

// ---- stats.json ----------------------------------------------------------------------

template <typename T>
json orNull(const std::optional<T>& value) {
  return value ? json(*value) : json(nullptr);
}

json toJson(const ConditionSummary& row) {
  const ScoreSummary& s = row.summary;
  json j = {{"attribute", row.attribute},
            {"condition", row.condition},
            {"n", s.n},
            {"mean", s.mean},
            {"median", s.median},
            {"q1", s.first_quartile},
            {"q3", s.third_quartile},
            {"min", s.minimum},
            {"max", s.maximum},
            {"sd", orNull(s.standard_deviation)},
            {"ci_low", orNull(s.ci_low)},
            {"ci_high", orNull(s.ci_high)}};
  if (!row.content.empty()) j["content"] = row.content;
  return j;
}

json toJson(const PairComparison& c) {
  const PairedTTest& t = c.t_test;
  const WilcoxonSignedRank& w = c.wilcoxon;
  return {{"attribute", c.attribute},
          {"first", c.pair.first},
          {"second", c.pair.second},
          {"n", t.n},
          {"mean_difference", orNull(t.mean_difference)},
          {"t_test",
           {{"testable", t.not_testable.empty()},
            {"reason", t.not_testable},
            {"t", orNull(t.t)},
            {"df", t.not_testable.empty() ? json(t.degrees_of_freedom) : json(nullptr)},
            {"p", orNull(t.p_value)},
            {"h", orNull(t.h)},
            {"holm_p", orNull(c.t_test_holm_p)}}},
          {"wilcoxon",
           {{"testable", w.not_testable.empty()},
            {"reason", w.not_testable},
            {"n", w.n},
            {"zero_differences_dropped", w.zero_differences},
            {"w_plus", w.w_plus},
            {"w_minus", w.w_minus},
            {"ties", w.ties},
            {"method", w.p_value ? json(toString(w.method)) : json(nullptr)},
            {"z", orNull(w.z)},
            {"p", orNull(w.p_value)},
            {"holm_p", orNull(c.wilcoxon_holm_p)}}}};
}

json statsJson(const Analysis& a) {
  const ScreeningOptions& o = a.screening_options;
  json screened = json::array();
  for (const ListenerScreening& l : a.screening.listeners) {
    json entry = {{"listener", l.listener},
                  {"pages", l.pages},
                  {"misidentifications", l.misidentifications},
                  {"reference_pages", l.reference_pages},
                  {"kept", l.kept},
                  {"reason", l.reason}};
    if (o.reference_score_rule) entry["reference_below_threshold"] = l.reference_below_threshold;
    screened.push_back(entry);
  }
  json excluded = json::array();
  for (const auto& e : a.results.incomplete) excluded.push_back({{"listener", e.listener}, {"reason", e.reason}});
  for (const auto& e : a.screening.excluded()) excluded.push_back({{"listener", e.listener}, {"reason", e.reason}});
  json summaries = json::array(), by_content = json::array(), tests = json::array();
  for (const auto& row : a.summaries) summaries.push_back(toJson(row));
  for (const auto& row : a.summaries_by_content) by_content.push_back(toJson(row));
  for (const auto& c : a.comparisons) tests.push_back(toJson(c));
  return {{"files", a.files},
          {"scale", toString(a.scale)},
          {"alpha", a.alpha},
          {"confidence", 1.0 - a.alpha},
          {"listeners", {{"total", a.results.listeners.size()}, {"kept", a.screening.kept()}, {"excluded", excluded}}},
          {"screening",
           {{"anchor_rule", o.anchor_rule},
            {"reference", o.reference},
            {"low_anchors", o.low_anchors},
            {"max_misidentifications", o.max_misidentifications},
            {"bs1534_rule", o.reference_score_rule},
            {"reference_threshold", o.reference_threshold},
            {"max_fraction_below", o.max_fraction_below},
            {"incomplete", a.results.incomplete.size()},
            {"listeners", screened}}},
          {"summaries", summaries},
          {"summaries_by_content", by_content},
          {"paired_tests", tests}};
}

// ---- report.md -----------------------------------------------------------------------

std::string cell(const std::string& text) {
  std::string escaped;
  for (char c : text) escaped += c == '|' ? std::string("\\|") : std::string(1, c);
  return escaped;
}

std::string fixed(double value, int decimals = 2) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(decimals) << value;
  return text.str();
}

std::string fixed(const std::optional<double>& value, int decimals = 2) {
  return value ? fixed(*value, decimals) : "-";
}

std::string pText(const std::optional<double>& p) {
  if (!p) return "-";
  if (*p >= 0.001) return fixed(*p, 4);
  std::ostringstream text;
  text << std::scientific << std::setprecision(2) << *p;
  return text.str();
}

void screeningSection(const Analysis& a, std::ostream& out) {
  const ScreeningOptions& o = a.screening_options;
  out << "## Listeners\n\n"
      << a.results.listeners.size() << " listeners, " << a.screening.kept().size() << " kept. Screening: ";
  if (o.anchor_rule) {
    std::string anchors;
    for (const auto& name : o.low_anchors) anchors += (anchors.empty() ? "`" : ", `") + name + "`";
    out << "anchor rule of Remaggi et al. (hidden reference `" << o.reference << "`, low anchors "
        << (anchors.empty() ? "none" : anchors) << "; more than " << o.max_misidentifications
        << " misidentifications exclude)";
  }
  if (o.reference_score_rule) {
    out << (o.anchor_rule ? "; " : "") << "ITU-R BS.1534-3 4.1.2 (reference below " << o.reference_threshold
        << " on more than " << 100.0 * o.max_fraction_below << " % of the pages excludes)";
  }
  // The reference-below-threshold column only where its rule applies (90 means nothing on 0-5).
  const bool below = o.reference_score_rule;
  out << ".\n\n| Listener | Pages | Anchor misidentifications | "
      << (below ? "Reference below " + fixed(o.reference_threshold, 0) + " | " : "") << "Result |\n|---|---|---|"
      << (below ? "---|" : "") << "---|\n";
  for (const auto& e : a.results.incomplete) {
    out << "| " << cell(e.listener) << " | - | - | " << (below ? "- | " : "") << "excluded: " << cell(e.reason)
        << " |\n";
  }
  for (const ListenerScreening& l : a.screening.listeners) {
    out << "| " << cell(l.listener) << " | " << l.pages << " | " << l.misidentifications << " | ";
    if (below) out << l.reference_below_threshold << " of " << l.reference_pages << " | ";
    out << (l.kept ? std::string("kept") : "excluded: " + cell(l.reason)) << " |\n";
  }
}

void summaryTable(const std::vector<ConditionSummary>& rows, double confidence, std::ostream& out) {
  std::string heading;
  for (const ConditionSummary& row : rows) {
    const std::string this_heading = row.attribute + (row.content.empty() ? "" : " / " + row.content);
    if (this_heading != heading) {
      heading = this_heading;
      out << "\n### " << cell(heading) << "\n\n| Condition | n | Mean | " << fixed(100.0 * confidence, 0)
          << " % CI | Median | Q1 | Q3 | SD |\n|---|---|---|---|---|---|---|---|\n";
    }
    const ScoreSummary& s = row.summary;
    out << "| " << cell(row.condition) << " | " << s.n << " | " << fixed(s.mean) << " | "
        << (s.ci_low ? fixed(s.ci_low) + " .. " + fixed(s.ci_high) : "-") << " | " << fixed(s.median) << " | "
        << fixed(s.first_quartile) << " | " << fixed(s.third_quartile) << " | " << fixed(s.standard_deviation)
        << " |\n";
  }
}

void pairedTestsSection(const Analysis& a, std::ostream& out) {
  out << "\n## Paired tests\n\nPer attribute, paired by listener and page. t: Student's paired t-test, two-sided; "
      << "h = 1 when p < " << a.alpha << " (as Remaggi et al., Table 2). Wilcoxon: signed-rank test, two-sided, "
      << "zero differences dropped (Wilcoxon's method); exact null distribution or normal approximation "
      << "(tie-corrected, continuity-corrected). Holm: Holm-Bonferroni adjusted over the attribute's pairs.\n\n";
  if (a.comparisons.empty()) {
    out << "No pairs to test (fewer than two conditions besides the anchors; name pairs with --pairs).\n";
    return;
  }
  out << "| Attribute | Pair | n | Mean difference | t | df | p | h | Holm p (t) | W+ | Wilcoxon p | Method | Holm p "
         "(Wilcoxon) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<std::string> notes;
  for (const PairComparison& c : a.comparisons) {
    const PairedTTest& t = c.t_test;
    const WilcoxonSignedRank& w = c.wilcoxon;
    const std::string pair = c.pair.first + " vs " + c.pair.second;
    out << "| " << cell(c.attribute) << " | " << cell(pair) << " | " << t.n << " | " << fixed(t.mean_difference)
        << " | " << fixed(t.t, 3) << " | " << (t.t ? fixed(t.degrees_of_freedom, 0) : "-") << " | " << pText(t.p_value)
        << " | " << (t.h ? std::to_string(*t.h) : "-") << " | " << pText(c.t_test_holm_p) << " | "
        << (w.p_value ? fixed(w.w_plus, 1) : "-") << " | " << pText(w.p_value) << " | "
        << (w.p_value ? (w.method == WilcoxonMethod::kExact ? "exact" : "normal approx.") : "-") << " | "
        << pText(c.wilcoxon_holm_p) << " |\n";
    if (!t.not_testable.empty())
      notes.push_back(c.attribute + ", " + pair + ": t-test not testable: " + t.not_testable);
    if (!w.not_testable.empty())
      notes.push_back(c.attribute + ", " + pair + ": Wilcoxon not testable: " + w.not_testable);
    if (w.zero_differences > 0 && w.p_value) {
      notes.push_back(c.attribute + ", " + pair + ": Wilcoxon dropped " + std::to_string(w.zero_differences) +
                      " zero differences, ranked " + std::to_string(w.n));
    }
  }
  if (!notes.empty()) out << "\n";
  for (const auto& note : notes) out << "- " << note << "\n";
}

std::string reportMarkdown(const Analysis& a) {
  std::ostringstream out;
  out << "# MUSHRA analysis\n\nFiles: ";
  for (std::size_t i = 0; i < a.files.size(); ++i) out << (i ? ", " : "") << "`" << a.files[i] << "`";
  out << ". Scale " << toString(a.scale) << ". Significance level " << a.alpha << ".\n\n";
  screeningSection(a, out);
  out << "\n## Scores per attribute and condition\n";
  summaryTable(a.summaries, 1.0 - a.alpha, out);
  out << "\n## Scores per attribute, content and condition\n";
  summaryTable(a.summaries_by_content, 1.0 - a.alpha, out);
  pairedTestsSection(a, out);
  return out.str();
}

// ---- analyze -------------------------------------------------------------------------

std::vector<std::string> nameList(const std::string& text) {
  if (text == "none") return {};
  return commaSeparated(text);
}

int runAnalyze(const std::vector<std::string>& raw) {
  const Arguments args(raw, {"out", "scale", "pairs", "reference", "low-anchors", "alpha"}, {});
  if (args.positional().empty()) throw UsageError("no results file given");
  if (!args.has("out")) throw UsageError("--out DIR is required");
  Analysis a;
  a.files = args.positional();
  a.scale = parseMushraScale(args.value("scale", "0-5"));
  a.alpha = args.doubleValue("alpha", 0.05);
  if (!(a.alpha > 0.0 && a.alpha < 1.0)) throw UsageError("--alpha must lie between 0 and 1");
  a.screening_options = defaultScreeningOptions(a.scale);
  a.screening_options.reference = args.value("reference", a.screening_options.reference);
  if (args.has("low-anchors")) a.screening_options.low_anchors = nameList(args.value("low-anchors", ""));

  a.results = readMushraResults(a.files, a.scale);
  if (a.results.ratings.empty()) {
    throw InputError("no listener completed the test (" + a.results.incomplete.front().listener + ": " +
                     a.results.incomplete.front().reason + ")");
  }
  a.screening = screenListeners(a.results.ratings, a.screening_options);
  const std::vector<std::string> kept = a.screening.kept();
  if (kept.empty()) {
    const ListenerExclusion first = a.screening.excluded().front();
    throw InputError("the screening excluded every listener (" + first.listener + ": " + first.reason + ")");
  }
  const std::vector<MushraRating> kept_ratings = ratingsOfListeners(a.results.ratings, kept);

  a.summaries = summarizeConditions(kept_ratings, false, 1.0 - a.alpha);
  a.summaries_by_content = summarizeConditions(kept_ratings, true, 1.0 - a.alpha);
  std::vector<std::string> anchors = a.screening_options.low_anchors;
  anchors.push_back(a.screening_options.reference);
  const std::vector<ConditionPair> pairs =
      args.has("pairs") ? parseConditionPairs(args.value("pairs", "")) : allConditionPairs(kept_ratings, anchors);
  a.comparisons = comparePairs(kept_ratings, pairs, a.alpha);
  const std::vector<BoxPlotPanel> box_plot_panels = collectBoxPlotPanels(kept_ratings);

  const std::filesystem::path out = args.value("out", "");
  createFolder(out.string());
  writeBoxPlotFiles(box_plot_panels, a.scale, out);
  writeTextFile((out / "stats.json").string(), statsJson(a).dump(2) + "\n");
  writeTextFile((out / "report.md").string(), reportMarkdown(a));
  std::cout << "kept " << kept.size() << " of " << a.results.listeners.size() << " listeners; wrote "
            << (out / "stats.json").string() << " and " << (out / "report.md").string() << "\n";
  return 0;
}

// ---- the mushra command ----------------------------------------------------------------

// The steps of a test, by the first argument.
const std::map<std::string, std::function<int(const std::vector<std::string>&)>>& mushraSteps() {
  static const std::map<std::string, std::function<int(const std::vector<std::string>&)>> steps = {
      {"make", runMushraMake}, {"serve", runMushraServe}, {"analyze", runAnalyze}};
  return steps;
}

int runMushra(const std::vector<std::string>& args) {
  std::string available;
  for (const auto& step : mushraSteps()) available += (available.empty() ? "" : ", ") + step.first;
  if (args.empty() || args.front().rfind("--", 0) == 0) {
    throw UsageError("name the step first: room_reverb mushra " + available + " ...");
  }
  const auto step = mushraSteps().find(args.front());
  if (step == mushraSteps().end()) {
    throw UsageError("unknown mushra subcommand '" + args.front() + "' (available: " + available + ")");
  }
  return step->second(std::vector<std::string>(args.begin() + 1, args.end()));
}

const CommandRegistration registration({"mushra",
                                        "MUSHRA listening tests: make a test from a plan, serve its page, analyze results",
                                        std::string(kMushraMakeHelp) + kMushraServeHelp + kAnalyzeHelp, runMushra});

}  // namespace
}  // namespace room_reverb::tool
