#pragma once
// Statistics of MUSHRA ratings as Remaggi et al. report them (section 4: scores per
// condition and content as box plots, Figure 4; paired t-tests between methods with the
// decision h at the 5 % level, Table 2), plus the Wilcoxon signed-rank test, which does
// not assume normal differences (scores on a 0-5 integer scale are far from normal), and
// Holm's correction for testing several pairs on one attribute.
//
// Nothing here returns NaN: a quantity that cannot be computed (a spread from one score,
// a test on too few pairs) is an empty optional with the reason stated beside it.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "room_reverb/listening/mushra_results.h"

namespace room_reverb::core {

// ---- Descriptive statistics ------------------------------------------------------------

struct ScoreSummary {
  std::size_t n = 0;
  double mean = 0.0;
  double median = 0.0;
  double first_quartile = 0.0;  // quantileLinear 0.25 (common/quantile.h)
  double third_quartile = 0.0;  // quantileLinear 0.75
  double minimum = 0.0;
  double maximum = 0.0;
  double confidence = 0.95;  // of the interval below
  // Sample standard deviation (divisor n - 1) and the interval mean -+ t(1 - a/2, n - 1)
  // s / sqrt(n) from Student's t; absent for a single score.
  std::optional<double> standard_deviation;
  std::optional<double> ci_low;
  std::optional<double> ci_high;
};

// InputError for no scores or a confidence outside (0, 1).
ScoreSummary summarizeScores(const std::vector<double>& scores, double confidence);

struct ScoreGroup {
  std::string attribute;
  std::string content;  // empty when pooled over every content
  std::string condition;
  std::vector<double> scores;  // every listener's score on every page of the group
};

// The scores per attribute and condition, pooled over rooms and contents, or split by
// content as well (the panels of the paper's Figure 4). Groups are ordered by attribute,
// then content, then condition, each in order of first appearance in `ratings`.
std::vector<ScoreGroup> groupScores(const std::vector<MushraRating>& ratings, bool split_by_content);

struct ConditionSummary {
  std::string attribute;
  std::string content;  // empty when pooled over every content
  std::string condition;
  ScoreSummary summary;
};
std::vector<ConditionSummary> summarizeConditions(const std::vector<MushraRating>& ratings, bool split_by_content,
                                                  double confidence);

// ---- Paired tests between conditions ---------------------------------------------------

struct ConditionPair {
  std::string first;
  std::string second;
};

// "a:b,c:d" as on the command line. InputError for an empty list, a pair without
// exactly one ':', an empty name, or a condition paired with itself.
std::vector<ConditionPair> parseConditionPairs(const std::string& text);

// Every pair of the rated conditions that are not among `anchors` (the hidden reference
// and the low anchors, whose place the screening already checks), in order of appearance.
std::vector<ConditionPair> allConditionPairs(const std::vector<MushraRating>& ratings,
                                             const std::vector<std::string>& anchors);

// first - second, one difference per listener and page (room, content, attribute) of
// `attribute` on which the listener rated both conditions, in order of appearance.
std::vector<double> pairedDifferences(const std::vector<MushraRating>& ratings, const std::string& attribute,
                                      const ConditionPair& pair);

// Student's paired t-test of zero mean difference, two-sided.
struct PairedTTest {
  std::size_t n = 0;         // pairs
  std::string not_testable;  // why there is no test; empty when there is one
  std::optional<double> mean_difference;
  std::optional<double> t;        // mean / (s / sqrt(n))
  double degrees_of_freedom = 0;  // n - 1
  std::optional<double> p_value;
  std::optional<int> h;  // 1 when p < alpha (the null hypothesis rejected), as Table 2
};
// Not testable for fewer than 2 pairs or differences that are all equal (no variance:
// the statistic is undefined). InputError for alpha outside (0, 1).
PairedTTest pairedTTest(const std::vector<double>& differences, double alpha);

enum class WilcoxonMethod {
  kExact,                // null distribution of W+ by enumeration: n <= 25 and no tied |d|
  kNormalApproximation,  // with the tie correction of the variance and a continuity correction
};
std::string toString(WilcoxonMethod method);

// Wilcoxon's signed-rank test of a distribution of differences symmetric about zero,
// two-sided. Zero differences are dropped before ranking (Wilcoxon's own method, not
// Pratt's); tied |d| get their mean rank.
struct WilcoxonSignedRank {
  std::size_t n_pairs = 0;           // differences given
  std::size_t zero_differences = 0;  // dropped
  std::size_t n = 0;                 // ranked: n_pairs - zero_differences
  std::string not_testable;          // why there is no test; empty when there is one
  double w_plus = 0.0;               // sum of the ranks of positive differences
  double w_minus = 0.0;
  bool ties = false;  // some |d| tied
  WilcoxonMethod method = WilcoxonMethod::kExact;
  std::optional<double> z;  // the normal approximation's statistic
  std::optional<double> p_value;
};
// Not testable when every difference is zero (n = 0 after dropping them).
WilcoxonSignedRank wilcoxonSignedRank(const std::vector<double>& differences);

// Holm's step-down adjustment (Holm 1979) of a family of p-values: the k-th smallest of m
// becomes max over j <= k of min(1, (m - j + 1) p_(j)). Empty entries (no test) are not
// part of the family and stay empty.
std::vector<std::optional<double>> holmAdjust(const std::vector<std::optional<double>>& p_values);

struct PairComparison {
  std::string attribute;
  ConditionPair pair;
  PairedTTest t_test;
  WilcoxonSignedRank wilcoxon;
  std::optional<double> t_test_holm_p;    // Holm over this attribute's pairs
  std::optional<double> wilcoxon_holm_p;  // likewise
};

// Both tests for every attribute and pair, pairing by listener and page; Holm's
// adjustment per attribute, over the pairs, for each test separately. InputError when a
// pair names a condition that no rating has, or alpha is outside (0, 1).
std::vector<PairComparison> comparePairs(const std::vector<MushraRating>& ratings,
                                         const std::vector<ConditionPair>& pairs, double alpha);

}  // namespace room_reverb::core
