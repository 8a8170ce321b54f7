#include "room_reverb/listening/mushra_statistics.h"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <map>
#include <numeric>
#include <sstream>
#include <tuple>

#include "room_reverb/common/error.h"
#include "room_reverb/common/quantile.h"
#include "room_reverb/common/sample_statistics.h"

namespace room_reverb::core {
namespace {

// Largest n for which the exact null distribution of W+ is used (the limit of scipy's
// wilcoxon before version 1.9; R's is 49). With ties the ranks are no
// longer 1..n and the enumeration below does not apply, so ties always take the normal
// approximation.
constexpr std::size_t kWilcoxonExactMaxN = 25;

void requireProbability(double value, const std::string& name) {
  if (!(value > 0.0 && value < 1.0)) {
    std::ostringstream text;
    text << name << " must lie between 0 and 1 (exclusive), got " << value;
    throw InputError(text.str());
  }
}

// Differences of scores read from decimal text are equal in value but not always in
// binary (72.3 - 70.1 vs 50.3 - 48.1); treat them as equal for zeros and ties.
bool sameValue(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max({1.0, std::abs(a), std::abs(b)}); }

// Position of `key` in `keys`, appending it when new: groups in order of appearance.
template <typename Key>
std::size_t indexOf(std::vector<Key>& keys, const Key& key) {
  const auto found = std::find(keys.begin(), keys.end(), key);
  if (found != keys.end()) return static_cast<std::size_t>(found - keys.begin());
  keys.push_back(key);
  return keys.size() - 1;
}

std::string numberText(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// Mean ranks (1-based) of `values`, ties (sameValue) sharing the mean of their ranks;
// `ties` tells whether there were any and `tie_term` is sum(t^3 - t) over tie groups.
std::vector<double> meanRanks(const std::vector<double>& values, bool& ties, double& tie_term) {
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(values.size());
  ties = false;
  tie_term = 0.0;
  for (std::size_t start = 0; start < order.size();) {
    std::size_t end = start + 1;
    while (end < order.size() && sameValue(values[order[end]], values[order[start]])) ++end;
    const double rank = 0.5 * static_cast<double>(start + 1 + end);  // mean of start+1 .. end
    for (std::size_t k = start; k < end; ++k) ranks[order[k]] = rank;
    const double t = static_cast<double>(end - start);
    if (end - start > 1) ties = true;
    tie_term += t * t * t - t;
    start = end;
  }
  return ranks;
}

// P(W+ <= w) and P(W+ >= w) under the null hypothesis for ranks 1..n without ties: each
// of the 2^n sign assignments is equally likely; the number with rank sum s follows from
// the recurrence over ranks (counts fit a double exactly up to 2^53).
std::pair<double, double> exactSignedRankTails(std::size_t n, double w) {
  const std::size_t total = n * (n + 1) / 2;
  std::vector<double> count(total + 1, 0.0);
  count[0] = 1.0;
  for (std::size_t rank = 1; rank <= n; ++rank) {
    for (std::size_t s = total; s >= rank; --s) count[s] += count[s - rank];
  }
  const double assignments = std::ldexp(1.0, static_cast<int>(n));
  double lower = 0.0, upper = 0.0;
  for (std::size_t s = 0; s <= total; ++s) {
    if (static_cast<double>(s) <= w + 1e-9) lower += count[s];
    if (static_cast<double>(s) >= w - 1e-9) upper += count[s];
  }
  return {lower / assignments, upper / assignments};
}

}  // namespace

// ---- Descriptive statistics ------------------------------------------------------------

ScoreSummary summarizeScores(const std::vector<double>& scores, double confidence) {
  if (scores.empty()) throw InputError("no scores to summarise");
  requireProbability(confidence, "the confidence level");
  std::vector<double> sorted = scores;
  std::sort(sorted.begin(), sorted.end());
  ScoreSummary summary;
  summary.n = sorted.size();
  summary.confidence = confidence;
  const double n = static_cast<double>(summary.n);
  summary.mean = sampleMean(sorted);
  summary.median = quantileLinear(sorted, 0.5);
  summary.first_quartile = quantileLinear(sorted, 0.25);
  summary.third_quartile = quantileLinear(sorted, 0.75);
  summary.minimum = sorted.front();
  summary.maximum = sorted.back();
  if (summary.n < 2) return summary;
  const double sd = sampleStandardDeviation(sorted);
  const boost::math::students_t t_distribution(n - 1.0);
  const double half_width =
      boost::math::quantile(boost::math::complement(t_distribution, (1.0 - confidence) / 2.0)) * sd / std::sqrt(n);
  summary.standard_deviation = sd;
  summary.ci_low = summary.mean - half_width;
  summary.ci_high = summary.mean + half_width;
  return summary;
}

std::vector<ScoreGroup> groupScores(const std::vector<MushraRating>& ratings, bool split_by_content) {
  std::vector<std::string> attributes, contents, conditions;
  std::map<std::tuple<std::size_t, std::size_t, std::size_t>, ScoreGroup> groups;
  for (const MushraRating& rating : ratings) {
    const std::string content = split_by_content ? rating.content : "";
    auto& group = groups[{indexOf(attributes, rating.attribute), indexOf(contents, content),
                          indexOf(conditions, rating.condition)}];
    if (group.scores.empty()) group = ScoreGroup{rating.attribute, content, rating.condition, {}};
    group.scores.push_back(rating.score);
  }
  std::vector<ScoreGroup> ordered;
  for (auto& entry : groups) ordered.push_back(std::move(entry.second));
  return ordered;
}

std::vector<ConditionSummary> summarizeConditions(const std::vector<MushraRating>& ratings, bool split_by_content,
                                                  double confidence) {
  std::vector<ConditionSummary> summaries;
  for (const ScoreGroup& group : groupScores(ratings, split_by_content)) {
    summaries.push_back({group.attribute, group.content, group.condition, summarizeScores(group.scores, confidence)});
  }
  return summaries;
}

// ---- Paired tests ----------------------------------------------------------------------

std::vector<ConditionPair> parseConditionPairs(const std::string& text) {
  std::vector<ConditionPair> pairs;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    const auto colon = item.find(':');
    if (colon == std::string::npos || item.find(':', colon + 1) != std::string::npos || colon == 0 ||
        colon + 1 == item.size()) {
      throw InputError("condition pair '" + item + "' is not of the form first:second");
    }
    ConditionPair pair{item.substr(0, colon), item.substr(colon + 1)};
    if (pair.first == pair.second) throw InputError("condition pair '" + item + "' pairs a condition with itself");
    pairs.push_back(pair);
  }
  if (pairs.empty()) throw InputError("no condition pair given (expected first:second[,first:second...])");
  return pairs;
}

std::vector<ConditionPair> allConditionPairs(const std::vector<MushraRating>& ratings,
                                             const std::vector<std::string>& anchors) {
  std::vector<std::string> conditions;
  for (const MushraRating& rating : ratings) {
    if (std::find(anchors.begin(), anchors.end(), rating.condition) == anchors.end()) {
      indexOf(conditions, rating.condition);
    }
  }
  std::vector<ConditionPair> pairs;
  for (std::size_t i = 0; i < conditions.size(); ++i) {
    for (std::size_t j = i + 1; j < conditions.size(); ++j) pairs.push_back({conditions[i], conditions[j]});
  }
  return pairs;
}

std::vector<double> pairedDifferences(const std::vector<MushraRating>& ratings, const std::string& attribute,
                                      const ConditionPair& pair) {
  // Per listener and page: the two scores, present or not.
  std::vector<std::pair<std::string, MushraTrial>> pages;
  std::vector<std::pair<std::optional<double>, std::optional<double>>> scores;
  for (const MushraRating& rating : ratings) {
    if (rating.attribute != attribute) continue;
    if (rating.condition != pair.first && rating.condition != pair.second) continue;
    const std::size_t page = indexOf(pages, std::make_pair(rating.listener, trialOf(rating)));
    scores.resize(pages.size());
    (rating.condition == pair.first ? scores[page].first : scores[page].second) = rating.score;
  }
  std::vector<double> differences;
  for (const auto& [first, second] : scores) {
    if (first && second) differences.push_back(*first - *second);
  }
  return differences;
}

PairedTTest pairedTTest(const std::vector<double>& differences, double alpha) {
  requireProbability(alpha, "alpha");
  PairedTTest test;
  test.n = differences.size();
  if (test.n < 2) {
    test.not_testable = std::to_string(test.n) + " pair" + (test.n == 1 ? "" : "s") + ": the t-test needs at least 2";
    return test;
  }
  const double n = static_cast<double>(test.n);
  const double mean = sampleMean(differences);
  test.mean_difference = mean;
  test.degrees_of_freedom = n - 1.0;
  const bool constant =
      std::all_of(differences.begin(), differences.end(), [&](double d) { return sameValue(d, differences.front()); });
  if (constant) {
    test.not_testable =
        "every difference is " + numberText(differences.front()) + ": no variance, so the t statistic is undefined";
    return test;
  }
  const double standard_error = sampleStandardDeviation(differences) / std::sqrt(n);
  test.t = mean / standard_error;
  const boost::math::students_t t_distribution(n - 1.0);
  test.p_value = 2.0 * boost::math::cdf(boost::math::complement(t_distribution, std::abs(*test.t)));
  test.h = *test.p_value < alpha ? 1 : 0;
  return test;
}

std::string toString(WilcoxonMethod method) {
  return method == WilcoxonMethod::kExact ? "exact"
                                          : "normal approximation (tie-corrected variance, continuity correction)";
}

WilcoxonSignedRank wilcoxonSignedRank(const std::vector<double>& differences) {
  WilcoxonSignedRank test;
  test.n_pairs = differences.size();
  std::vector<double> nonzero;
  for (double d : differences) {
    if (sameValue(d, 0.0))
      ++test.zero_differences;
    else
      nonzero.push_back(d);
  }
  test.n = nonzero.size();
  if (test.n == 0) {
    test.not_testable = test.n_pairs == 0 ? "no pairs"
                                          : "all " + std::to_string(test.n_pairs) +
                                                " differences are zero (dropped, Wilcoxon's method): nothing to rank";
    return test;
  }
  std::vector<double> magnitudes(nonzero.size());
  std::transform(nonzero.begin(), nonzero.end(), magnitudes.begin(), [](double d) { return std::abs(d); });
  double tie_term = 0.0;
  const std::vector<double> ranks = meanRanks(magnitudes, test.ties, tie_term);
  for (std::size_t i = 0; i < nonzero.size(); ++i) (nonzero[i] > 0.0 ? test.w_plus : test.w_minus) += ranks[i];

  const double n = static_cast<double>(test.n);
  if (!test.ties && test.n <= kWilcoxonExactMaxN) {
    test.method = WilcoxonMethod::kExact;
    const auto [lower, upper] = exactSignedRankTails(test.n, test.w_plus);
    test.p_value = std::min(1.0, 2.0 * std::min(lower, upper));
    return test;
  }
  // W+ has mean n(n+1)/4 and variance n(n+1)(2n+1)/24, less sum(t^3 - t)/48 for ties
  // (e.g. Hollander, Wolfe and Chicken, Nonparametric Statistical Methods, sec. 3.1);
  // the variance is positive for any n >= 1. The continuity correction moves |W+ - mean|
  // half a unit towards zero, never past it.
  test.method = WilcoxonMethod::kNormalApproximation;
  const double mean = n * (n + 1.0) / 4.0;
  const double variance = n * (n + 1.0) * (2.0 * n + 1.0) / 24.0 - tie_term / 48.0;
  const double z = std::max(0.0, std::abs(test.w_plus - mean) - 0.5) / std::sqrt(variance);
  test.z = test.w_plus >= mean ? z : -z;
  const boost::math::normal standard_normal;
  test.p_value = std::min(1.0, 2.0 * boost::math::cdf(boost::math::complement(standard_normal, z)));
  return test;
}

std::vector<std::optional<double>> holmAdjust(const std::vector<std::optional<double>>& p_values) {
  std::vector<std::size_t> family;
  for (std::size_t i = 0; i < p_values.size(); ++i) {
    if (p_values[i]) family.push_back(i);
  }
  std::stable_sort(family.begin(), family.end(),
                   [&](std::size_t a, std::size_t b) { return *p_values[a] < *p_values[b]; });
  std::vector<std::optional<double>> adjusted(p_values.size());
  const double m = static_cast<double>(family.size());
  double running_max = 0.0;  // keeps the adjusted values in the order of the raw ones
  for (std::size_t k = 0; k < family.size(); ++k) {
    running_max = std::max(running_max, std::min(1.0, (m - static_cast<double>(k)) * *p_values[family[k]]));
    adjusted[family[k]] = running_max;
  }
  return adjusted;
}

std::vector<PairComparison> comparePairs(const std::vector<MushraRating>& ratings,
                                         const std::vector<ConditionPair>& pairs, double alpha) {
  requireProbability(alpha, "alpha");
  std::vector<std::string> attributes, conditions;
  for (const MushraRating& rating : ratings) {
    indexOf(attributes, rating.attribute);
    indexOf(conditions, rating.condition);
  }
  for (const ConditionPair& pair : pairs) {
    for (const std::string& name : {pair.first, pair.second}) {
      if (std::find(conditions.begin(), conditions.end(), name) == conditions.end()) {
        std::string known;
        for (const auto& condition : conditions) known += (known.empty() ? "" : ", ") + condition;
        throw InputError("pair " + pair.first + ":" + pair.second + " names condition '" + name +
                         "', which no rating has (conditions: " + known + ")");
      }
    }
  }
  std::vector<PairComparison> comparisons;
  for (const std::string& attribute : attributes) {
    const std::size_t family_start = comparisons.size();
    std::vector<std::optional<double>> t_p, wilcoxon_p;
    for (const ConditionPair& pair : pairs) {
      const std::vector<double> differences = pairedDifferences(ratings, attribute, pair);
      PairComparison comparison{attribute, pair, pairedTTest(differences, alpha), wilcoxonSignedRank(differences),
                                {},        {}};
      if (differences.empty()) {
        comparison.t_test.not_testable = comparison.wilcoxon.not_testable =
            "no page of '" + attribute + "' on which a listener rated both";
      }
      t_p.push_back(comparison.t_test.p_value);
      wilcoxon_p.push_back(comparison.wilcoxon.p_value);
      comparisons.push_back(std::move(comparison));
    }
    const auto t_holm = holmAdjust(t_p);
    const auto wilcoxon_holm = holmAdjust(wilcoxon_p);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      comparisons[family_start + k].t_test_holm_p = t_holm[k];
      comparisons[family_start + k].wilcoxon_holm_p = wilcoxon_holm[k];
    }
  }
  return comparisons;
}

}  // namespace room_reverb::core
