// MUSHRA results, post-screening and statistics. Reference values are
// computed here by other routes than the library's (the t-test's p from the regularised
// incomplete beta function, the exact Wilcoxon p by enumerating every sign assignment)
// or taken from textbook examples (R's documentation: Student's sleep data, Hollander and
// Wolfe's depression data).
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/math/special_functions/beta.hpp>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "room_reverb/common/quantile.h"
#include "room_reverb/common/sample_statistics.h"
#include "room_reverb/listening/mushra_results.h"
#include "room_reverb/listening/mushra_screening.h"
#include "room_reverb/listening/mushra_statistics.h"
#include "test_files.h"

using namespace room_reverb::core;
using room_reverb::test::expectInputError;
using room_reverb::test::writeFile;

namespace {

const char* kHeader = "listener,page,room,content,attribute,condition,letter,score,duration_s\n";

MushraRating rating(const std::string& listener, const std::string& page, const std::string& condition, double score,
                    const std::string& content = "speech", const std::string& attribute = "overall") {
  MushraRating r;
  r.listener = listener;
  r.page = page;
  r.room = "lab";
  r.content = content;
  r.attribute = attribute;
  r.condition = condition;
  r.letter = "A";
  r.score = score;
  r.origin = "test";
  return r;
}

// One listener's pages p1.. with the scores of each condition on each page.
std::vector<MushraRating> listenerPages(const std::string& listener,
                                        const std::vector<std::map<std::string, double>>& pages) {
  std::vector<MushraRating> ratings;
  for (std::size_t p = 0; p < pages.size(); ++p) {
    const std::string content = p % 2 == 0 ? "speech" : "music";
    for (const auto& [condition, score] : pages[p]) {
      ratings.push_back(
          rating(listener, "p" + std::to_string(p + 1), condition, score, content, p < 2 ? "spatial" : "overall"));
    }
  }
  return ratings;
}

void append(std::vector<MushraRating>& to, const std::vector<MushraRating>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

// Two-sided p of Student's t with `df` degrees of freedom, by the identity
// P(|T| > t) = I_{df / (df + t^2)}(df / 2, 1 / 2), not by the t distribution's cdf.
double twoSidedTPByBeta(double t, double df) { return boost::math::ibeta(df / 2.0, 0.5, df / (df + t * t)); }

// The exact two-sided Wilcoxon p of untied ranks 1..n by enumerating all 2^n signs.
double exactWilcoxonByEnumeration(int n, double w_plus) {
  double lower = 0, upper = 0;
  for (unsigned mask = 0; mask < (1u << n); ++mask) {
    double sum = 0;
    for (int rank = 1; rank <= n; ++rank) {
      if (mask & (1u << (rank - 1))) sum += rank;
    }
    if (sum <= w_plus) ++lower;
    if (sum >= w_plus) ++upper;
  }
  return std::min(1.0, 2.0 * std::min(lower, upper) / std::ldexp(1.0, n));
}

}  // namespace

// ---- Reading results -------------------------------------------------------------------

TEST(MushraResults, ReadsColumnsInAnyOrderQuotedFieldsAndExtraColumns) {
  const std::string text =
      "\xEF\xBB\xBFscore,condition,browser,listener,page,room,content,attribute,letter,duration_s\r\n"
      "4,rsao,firefox,ann,1,lab,\"speech, \"\"male\"\"\",overall,B,12.5\r\n"
      "\r\n"
      "5,reference,\"multi\nline\",ann,1,lab,\"speech, \"\"male\"\"\",overall,A,3\r\n";
  const auto ratings = parseMushraResultsCsv(text, "a.csv", MushraScale::kZeroToFive);
  ASSERT_EQ(ratings.size(), 2u);
  EXPECT_EQ(ratings[0].listener, "ann");
  EXPECT_EQ(ratings[0].content, "speech, \"male\"");
  EXPECT_EQ(ratings[0].condition, "rsao");
  EXPECT_EQ(ratings[0].letter, "B");
  EXPECT_DOUBLE_EQ(ratings[0].score, 4.0);
  EXPECT_DOUBLE_EQ(ratings[0].duration_s, 12.5);
  EXPECT_EQ(ratings[0].origin, "a.csv:2");
  EXPECT_EQ(ratings[1].origin, "a.csv:4");
  EXPECT_EQ(ratings[1].condition, "reference");
}

TEST(MushraResults, MissingColumnsAreNamed) {
  expectInputError(
      [] {
        parseMushraResultsCsv("listener,page,room,content,attribute,condition,duration_s\nx,1,r,c,a,k,1\n", "m.csv",
                              MushraScale::kZeroToFive);
      },
      {"m.csv", "missing columns", "'letter'", "'score'"});
}

TEST(MushraResults, ScoresOutsideTheScaleAreRefused) {
  const auto row = [](const std::string& score) {
    return std::string(kHeader) + "ann,1,lab,speech,overall,rsao,A," + score + ",2\n";
  };
  expectInputError([&] { parseMushraResultsCsv(row("6"), "s.csv", MushraScale::kZeroToFive); },
                   {"s.csv:2", "score 6", "outside the 0-5 scale"});
  expectInputError([&] { parseMushraResultsCsv(row("-1"), "s.csv", MushraScale::kZeroToFive); },
                   {"outside the 0-5 scale"});
  expectInputError([&] { parseMushraResultsCsv(row("101"), "s.csv", MushraScale::kZeroToHundred); },
                   {"outside the 0-100 scale"});
  expectInputError([&] { parseMushraResultsCsv(row("3.5"), "s.csv", MushraScale::kZeroToFive); }, {"not an integer"});
  EXPECT_DOUBLE_EQ(parseMushraResultsCsv(row("72.5"), "s.csv", MushraScale::kZeroToHundred)[0].score, 72.5);
}

TEST(MushraResults, UnparseableNumbersAreRefused) {
  const std::string head = kHeader;
  expectInputError(
      [&] {
        parseMushraResultsCsv(head + "ann,1,lab,speech,overall,rsao,A,four,2\n", "u.csv", MushraScale::kZeroToFive);
      },
      {"u.csv:2", "score 'four' is not a number"});
  expectInputError(
      [&] {
        parseMushraResultsCsv(head + "ann,1,lab,speech,overall,rsao,A,nan,2\n", "u.csv", MushraScale::kZeroToHundred);
      },
      {"'nan' is not a number"});
  expectInputError(
      [&] {
        parseMushraResultsCsv(head + "ann,1,lab,speech,overall,rsao,A,3,soon\n", "u.csv", MushraScale::kZeroToFive);
      },
      {"duration_s 'soon'"});
  expectInputError(
      [&] { parseMushraResultsCsv(head + "ann,1,lab,speech,overall,rsao,3,2\n", "u.csv", MushraScale::kZeroToFive); },
      {"u.csv:2", "8 fields where the header has 9"});
  expectInputError(
      [&] {
        parseMushraResultsCsv(head + "ann,1,lab,\"speech,overall,rsao,A,3,2\n", "u.csv", MushraScale::kZeroToFive);
      },
      {"unterminated quoted field"});
}

TEST(MushraResults, EmptyFilesAndNoFilesAreRefused) {
  expectInputError([] { parseMushraResultsCsv("", "e.csv", MushraScale::kZeroToFive); },
                   {"e.csv", "empty results file"});
  expectInputError([] { parseMushraResultsCsv(" \n\n", "e.csv", MushraScale::kZeroToFive); }, {"empty results file"});
  expectInputError([] { parseMushraResultsCsv(kHeader, "h.csv", MushraScale::kZeroToFive); }, {"h.csv", "no ratings"});
  expectInputError([] { readMushraResults({}, MushraScale::kZeroToFive); }, {"no results file"});
  expectInputError([] { readMushraResults({"/nonexistent/r.csv"}, MushraScale::kZeroToFive); },
                   {"/nonexistent/r.csv", "no such file"});
}

TEST(MushraResults, MergesFilesAndRefusesDuplicateRatings) {
  const std::string a = writeFile("mushra_a.csv", std::string(kHeader) +
                                                      "ann,1,lab,speech,overall,rsao,A,3,2\n"
                                                      "ann,1,lab,speech,overall,reference,B,5,2\n");
  const std::string b = writeFile("mushra_b.csv", std::string(kHeader) +
                                                      "bob,1,lab,speech,overall,rsao,B,2,2\n"
                                                      "bob,1,lab,speech,overall,reference,A,4,2\n");
  const MushraResults merged = readMushraResults({a, b}, MushraScale::kZeroToFive);
  EXPECT_EQ(merged.ratings.size(), 4u);
  EXPECT_EQ(merged.listeners, (std::vector<std::string>{"ann", "bob"}));
  EXPECT_TRUE(merged.incomplete.empty());

  const std::string again =
      writeFile("mushra_again.csv", std::string(kHeader) + "ann,1,lab,speech,overall,rsao,C,4,2\n");
  expectInputError(
      [&] {
        readMushraResults({a, again}, MushraScale::kZeroToFive);
      },
      {"'ann'", "'rsao' twice", a + ":2", again + ":2"});
}

TEST(MushraResults, APageMustAskOneThingOnce) {
  std::vector<MushraRating> two_attributes = {rating("ann", "p1", "rsao", 3),
                                              rating("ann", "p1", "fast", 3, "speech", "spatial")};
  expectInputError([&] { combineMushraRatings(two_attributes); }, {"'ann'", "page 'p1'"});
  std::vector<MushraRating> two_pages = {rating("ann", "p1", "rsao", 3), rating("ann", "p2", "fast", 3)};
  expectInputError([&] { combineMushraRatings(two_pages); }, {"two pages"});
}

TEST(MushraResults, AListenerWithMissingPagesIsAStatedExclusion) {
  const std::map<std::string, double> page = {{"reference", 5}, {"rsao", 3}, {"wrong_room", 0}};
  std::vector<MushraRating> ratings;
  append(ratings, listenerPages("ann", {page, page, page, page}));
  append(ratings, listenerPages("bob", {page, page, page}));  // left before the last page
  auto carl = listenerPages("carl", {page, page, page, page});
  carl.pop_back();  // skipped one stimulus on the last page
  append(ratings, carl);
  const MushraResults results = combineMushraRatings(ratings);
  EXPECT_EQ(results.listeners, (std::vector<std::string>{"ann", "bob", "carl"}));
  ASSERT_EQ(results.incomplete.size(), 2u);
  EXPECT_EQ(results.incomplete[0].listener, "bob");
  EXPECT_NE(results.incomplete[0].reason.find("rated 3 of 4 pages"), std::string::npos) << results.incomplete[0].reason;
  EXPECT_NE(results.incomplete[0].reason.find("lab / music / overall"), std::string::npos)
      << results.incomplete[0].reason;
  EXPECT_EQ(results.incomplete[1].listener, "carl");
  EXPECT_NE(results.incomplete[1].reason.find("no rating for wrong_room"), std::string::npos)
      << results.incomplete[1].reason;
  EXPECT_EQ(results.ratings.size(), 12u);
  for (const auto& r : results.ratings) EXPECT_EQ(r.listener, "ann");
}

// ---- Screening -------------------------------------------------------------------------

TEST(MushraScreening, AnchorMisidentificationFollowsTheStatedDefinition) {
  ScreeningOptions options;
  options.low_anchors = {"wrong_room", "lowpass_3k5"};
  auto page = [](double reference, double rsao, double accurate, double wrong_room, double lowpass) {
    return std::vector<MushraRating>{rating("x", "p", "reference", reference), rating("x", "p", "rsao", rsao),
                                     rating("x", "p", "accurate", accurate), rating("x", "p", "wrong_room", wrong_room),
                                     rating("x", "p", "lowpass_3k5", lowpass)};
  };
  EXPECT_EQ(checkPageAnchors(page(5, 3, 4, 0, 1), options).misidentifications(), 0);
  EXPECT_EQ(checkPageAnchors(page(5, 3, 4, 1, 0), options).misidentifications(), 0);  // anchors' order is free
  EXPECT_EQ(checkPageAnchors(page(4, 3, 4, 0, 1), options).misidentifications(), 0);  // reference ties the highest
  EXPECT_EQ(checkPageAnchors(page(5, 3, 4, 3, 1), options).misidentifications(), 0);  // anchor ties the lowest
  const PageAnchorCheck reference_low = checkPageAnchors(page(3, 3, 4, 0, 1), options);
  EXPECT_TRUE(reference_low.reference_misidentified);
  EXPECT_EQ(reference_low.misidentifications(), 1);
  const PageAnchorCheck all_wrong = checkPageAnchors(page(2, 3, 4, 5, 4), options);
  EXPECT_EQ(all_wrong.low_anchors_rated, 2);
  EXPECT_EQ(all_wrong.low_anchors_misidentified, 2);
  EXPECT_EQ(all_wrong.misidentifications(), 3);
}

TEST(MushraScreening, PaperRuleExcludesMoreThanTwoMisidentifications) {
  ScreeningOptions options = defaultScreeningOptions(MushraScale::kZeroToFive);
  options.low_anchors = {"wrong_room", "lowpass_3k5"};
  EXPECT_FALSE(options.reference_score_rule);
  using Page = std::map<std::string, double>;
  const Page clean = {{"reference", 5}, {"rsao", 3}, {"accurate", 4}, {"wrong_room", 0}, {"lowpass_3k5", 1}};
  const Page reference_missed = {{"reference", 3}, {"rsao", 3}, {"accurate", 4}, {"wrong_room", 0}, {"lowpass_3k5", 1}};
  const Page anchor_missed = {{"reference", 5}, {"rsao", 2}, {"accurate", 4}, {"wrong_room", 3}, {"lowpass_3k5", 1}};
  const Page both_missed = {{"reference", 3}, {"rsao", 2}, {"accurate", 4}, {"wrong_room", 3}, {"lowpass_3k5", 1}};
  const Page ties_only = {{"reference", 4}, {"rsao", 2}, {"accurate", 4}, {"wrong_room", 1}, {"lowpass_3k5", 2}};
  std::vector<MushraRating> ratings;
  append(ratings, listenerPages("clean", {clean, clean, clean, clean}));
  append(ratings, listenerPages("twice", {reference_missed, anchor_missed, ties_only, clean}));
  append(ratings, listenerPages("three", {both_missed, anchor_missed, clean, ties_only}));
  append(ratings, listenerPages("many", {both_missed, both_missed, both_missed, both_missed}));
  const ScreeningResult result = screenListeners(ratings, options);
  ASSERT_EQ(result.listeners.size(), 4u);
  EXPECT_EQ(result.listeners[1].misidentifications, 2);
  EXPECT_EQ(result.listeners[2].misidentifications, 3);
  EXPECT_EQ(result.listeners[3].misidentifications, 8);
  EXPECT_EQ(result.kept(), (std::vector<std::string>{"clean", "twice"}));
  const auto excluded = result.excluded();
  ASSERT_EQ(excluded.size(), 2u);
  EXPECT_EQ(excluded[0].listener, "three");
  EXPECT_NE(excluded[0].reason.find("misidentified the anchors 3 times"), std::string::npos) << excluded[0].reason;

  const auto kept_ratings = ratingsOfListeners(ratings, result.kept());
  EXPECT_EQ(kept_ratings.size(), 40u);
}

TEST(MushraScreening, Bs1534RuleExcludesReferenceBelow90OnMoreThan15Percent) {
  const ScreeningOptions options = defaultScreeningOptions(MushraScale::kZeroToHundred);
  EXPECT_TRUE(options.reference_score_rule);
  EXPECT_TRUE(options.anchor_rule);
  auto listener = [](const std::string& name, int pages_below_90) {
    std::vector<MushraRating> ratings;
    for (int p = 0; p < 7; ++p) {  // 1 of 7 pages is 14.3 % (kept), 2 of 7 are 28.6 % (excluded)
      const std::string page = "p" + std::to_string(p);
      const double reference = p < pages_below_90 ? 85.0 : 100.0;
      ratings.push_back(rating(name, page, "reference", reference, "c" + std::to_string(p)));
      ratings.push_back(rating(name, page, "rsao", 60.0, "c" + std::to_string(p)));
      ratings.push_back(rating(name, page, "wrong_room", 10.0, "c" + std::to_string(p)));
    }
    return ratings;
  };
  std::vector<MushraRating> ratings;
  append(ratings, listener("none_below", 0));
  append(ratings, listener("one_below", 1));
  append(ratings, listener("two_below", 2));
  const ScreeningResult result = screenListeners(ratings, options);
  EXPECT_EQ(result.kept(), (std::vector<std::string>{"none_below", "one_below"}));
  ASSERT_EQ(result.excluded().size(), 1u);
  EXPECT_EQ(result.listeners[2].reference_below_threshold, 2u);
  EXPECT_EQ(result.listeners[2].reference_pages, 7u);
  EXPECT_NE(result.excluded()[0].reason.find("BS.1534-3"), std::string::npos) << result.excluded()[0].reason;
}

TEST(MushraScreening, RulesNamingAbsentConditionsAreRefused) {
  const std::vector<MushraRating> ratings = {rating("ann", "p1", "hidden_ref", 5),
                                             rating("ann", "p1", "wrong_room", 0)};
  expectInputError([&] { screenListeners(ratings, ScreeningOptions{}); }, {"'reference'", "--reference"});
  ScreeningOptions options;
  options.reference = "hidden_ref";
  options.low_anchors = {"lowpass_3k5"};
  expectInputError([&] { screenListeners(ratings, options); }, {"'lowpass_3k5'", "--low-anchors"});
  options.low_anchors = {};
  EXPECT_EQ(screenListeners(ratings, options).kept().size(), 1u);
}

// ---- Descriptive statistics ------------------------------------------------------------

TEST(MushraStatistics, QuartilesInterpolateLinearlyAsNumpy) {
  // numpy.percentile([1, 2, 3, 4], [10, 25, 50, 75]) = [1.3, 1.75, 2.5, 3.25]
  const std::vector<double> four = {1, 2, 3, 4};
  EXPECT_DOUBLE_EQ(quantileLinear(four, 0.10), 1.3);
  EXPECT_DOUBLE_EQ(quantileLinear(four, 0.25), 1.75);
  EXPECT_DOUBLE_EQ(quantileLinear(four, 0.50), 2.5);
  EXPECT_DOUBLE_EQ(quantileLinear(four, 0.75), 3.25);
  EXPECT_DOUBLE_EQ(quantileLinear(four, 1.0), 4.0);
  const ScoreSummary s = summarizeScores({9, 1, 7, 3, 5}, 0.95);
  EXPECT_DOUBLE_EQ(s.first_quartile, 3.0);
  EXPECT_DOUBLE_EQ(s.median, 5.0);
  EXPECT_DOUBLE_EQ(s.third_quartile, 7.0);
  EXPECT_DOUBLE_EQ(s.minimum, 1.0);
  EXPECT_DOUBLE_EQ(s.maximum, 9.0);
}

TEST(MushraStatistics, ConfidenceIntervalIsStudentsT) {
  const std::vector<double> scores = {3, 4, 4, 5, 2, 3, 4, 5, 3, 4};
  const ScoreSummary s = summarizeScores(scores, 0.95);
  const double n = 10, mean = 3.7;
  double squares = 0;
  for (double x : scores) squares += (x - mean) * (x - mean);
  const double sd = std::sqrt(squares / (n - 1));
  // t(0.975, 9) from the incomplete beta: P(|T| > t) = 0.05 at x = df / (df + t^2).
  const double x = boost::math::ibeta_inv(4.5, 0.5, 0.05);
  const double t_975 = std::sqrt(9.0 * (1.0 - x) / x);
  EXPECT_NEAR(t_975, 2.262157, 1e-6);  // tables of Student's t
  EXPECT_DOUBLE_EQ(s.mean, mean);
  ASSERT_TRUE(s.standard_deviation && s.ci_low && s.ci_high);
  EXPECT_NEAR(*s.standard_deviation, sd, 1e-12);
  EXPECT_NEAR(*s.ci_low, mean - t_975 * sd / std::sqrt(n), 1e-9);
  EXPECT_NEAR(*s.ci_high, mean + t_975 * sd / std::sqrt(n), 1e-9);

  const ScoreSummary single = summarizeScores({4}, 0.95);
  EXPECT_EQ(single.n, 1u);
  EXPECT_FALSE(single.standard_deviation || single.ci_low || single.ci_high);
  expectInputError([] { summarizeScores({}, 0.95); }, {"no scores"});
}

TEST(MushraStatistics, SyntheticRatingsReproduceTheirMeans) {
  const std::map<std::string, double> true_means = {
      {"reference", 92}, {"accurate", 70}, {"fast", 55}, {"rsao", 60}, {"wrong_room", 15}};
  std::mt19937 rng(20190611);
  std::normal_distribution<double> noise(0.0, 8.0);
  std::vector<MushraRating> ratings;
  for (int listener = 0; listener < 40; ++listener) {
    for (int page = 0; page < 4; ++page) {
      for (const auto& [condition, mean] : true_means) {
        const double score = std::clamp(mean + noise(rng), 0.0, 100.0);
        ratings.push_back(rating("l" + std::to_string(listener), "p" + std::to_string(page), condition, score,
                                 page % 2 ? "music" : "speech", page < 2 ? "spatial" : "overall"));
      }
    }
  }
  const auto summaries = summarizeConditions(ratings, false, 0.95);
  ASSERT_EQ(summaries.size(), 10u);  // 2 attributes x 5 conditions
  for (const auto& row : summaries) {
    EXPECT_EQ(row.summary.n, 80u);
    // Standard error 8 / sqrt(80) = 0.9 (less where clamping at 100 bites the reference).
    EXPECT_NEAR(row.summary.mean, true_means.at(row.condition), 2.7) << row.attribute << " " << row.condition;
    EXPECT_NEAR(*row.summary.standard_deviation, 8.0, 1.5) << row.condition;
  }
  const auto by_content = summarizeConditions(ratings, true, 0.95);
  ASSERT_EQ(by_content.size(), 20u);
  EXPECT_EQ(by_content.front().content, "speech");
  EXPECT_EQ(by_content.front().summary.n, 40u);

  const auto comparisons = comparePairs(ratings, {{"accurate", "fast"}, {"rsao", "fast"}}, 0.05);
  ASSERT_EQ(comparisons.size(), 4u);
  for (const auto& c : comparisons) {
    EXPECT_EQ(c.t_test.n, 80u);
    EXPECT_EQ(c.t_test.h, 1) << c.pair.first;
    EXPECT_EQ(c.wilcoxon.method, WilcoxonMethod::kNormalApproximation);  // n = 80 > 25
    EXPECT_LT(*c.wilcoxon.p_value, 0.05);
  }
  EXPECT_NEAR(*comparisons[0].t_test.mean_difference, 15.0, 3.0);
}

// ---- Paired tests ----------------------------------------------------------------------

TEST(MushraStatistics, PairedTTestMatchesAHandComputation) {
  const std::vector<double> differences = {1, 0, 1, 1, 2, 0, 1, 2, -1, 1};
  const double n = 10, mean = 0.8;
  double squares = 0;
  for (double d : differences) squares += (d - mean) * (d - mean);
  const double t = mean / (std::sqrt(squares / (n - 1)) / std::sqrt(n));
  const PairedTTest test = pairedTTest(differences, 0.05);
  ASSERT_TRUE(test.not_testable.empty()) << test.not_testable;
  EXPECT_NEAR(*test.t, t, 1e-12);
  EXPECT_DOUBLE_EQ(test.degrees_of_freedom, 9.0);
  EXPECT_NEAR(*test.p_value, twoSidedTPByBeta(t, 9.0), 1e-6);
  EXPECT_EQ(*test.h, *test.p_value < 0.05 ? 1 : 0);
  EXPECT_EQ(*pairedTTest({0.5, 0.1, -0.2}, 0.05).h, 0);
}

TEST(MushraStatistics, PairedTTestReproducesStudentsSleepData) {
  // Cushny and Peebles' sleep data as in R's example t.test(extra ~ group, data = sleep,
  // paired = TRUE): t = -4.0621, df = 9, p-value = 0.002833, mean difference -1.58.
  const std::vector<double> drug1 = {0.7, -1.6, -0.2, -1.2, -0.1, 3.4, 3.7, 0.8, 0.0, 2.0};
  const std::vector<double> drug2 = {1.9, 0.8, 1.1, 0.1, -0.1, 4.4, 5.5, 1.6, 4.6, 3.4};
  std::vector<double> differences;
  for (std::size_t i = 0; i < drug1.size(); ++i) differences.push_back(drug1[i] - drug2[i]);
  const PairedTTest test = pairedTTest(differences, 0.05);
  EXPECT_NEAR(*test.mean_difference, -1.58, 1e-12);
  EXPECT_NEAR(*test.t, -4.0621, 5e-5);
  EXPECT_NEAR(*test.p_value, 0.002833, 5e-7);
  EXPECT_EQ(*test.h, 1);

  // R's wilcox.test(drug1, drug2, paired = TRUE): V = 0, p-value = 0.009091 (one zero
  // difference dropped, one tie: normal approximation with continuity correction).
  const WilcoxonSignedRank w = wilcoxonSignedRank(differences);
  EXPECT_EQ(w.zero_differences, 1u);
  EXPECT_EQ(w.n, 9u);
  EXPECT_TRUE(w.ties);
  EXPECT_EQ(w.method, WilcoxonMethod::kNormalApproximation);
  EXPECT_DOUBLE_EQ(w.w_plus, 0.0);
  EXPECT_NEAR(*w.p_value, 0.009091, 5e-7);
}

TEST(MushraStatistics, PairedTTestStatesWhyItCannotTest) {
  EXPECT_FALSE(pairedTTest({}, 0.05).p_value);
  const PairedTTest one = pairedTTest({1.0}, 0.05);
  EXPECT_FALSE(one.t || one.p_value || one.h);
  EXPECT_NE(one.not_testable.find("at least 2"), std::string::npos) << one.not_testable;
  const PairedTTest constant = pairedTTest({1.0, 1.0, 1.0}, 0.05);
  EXPECT_FALSE(constant.p_value);
  EXPECT_NE(constant.not_testable.find("no variance"), std::string::npos) << constant.not_testable;
  expectInputError([] { pairedTTest({1, 2, 3}, 1.5); }, {"alpha"});
}

TEST(MushraStatistics, WilcoxonExactMatchesEnumerationOfAllSigns) {
  // Untied magnitudes; ranks of |d|: 0.5->1, 1.5->2, 2->3, 3->4, 4.5->5, 5->6, 6->7, 7->8.
  const std::vector<double> differences = {3, -0.5, 4.5, 0, 6, -2, 7, 1.5, 5, 0};
  const WilcoxonSignedRank w = wilcoxonSignedRank(differences);
  EXPECT_EQ(w.n_pairs, 10u);
  EXPECT_EQ(w.zero_differences, 2u);
  EXPECT_EQ(w.n, 8u);
  EXPECT_FALSE(w.ties);
  EXPECT_EQ(w.method, WilcoxonMethod::kExact);
  EXPECT_DOUBLE_EQ(w.w_minus, 1 + 3);
  EXPECT_DOUBLE_EQ(w.w_plus, 36 - 4);
  EXPECT_NEAR(*w.p_value, exactWilcoxonByEnumeration(8, 32), 1e-12);

  // Hollander and Wolfe's depression data, R's wilcox.test(x, y, paired = TRUE,
  // alternative = "greater"): V = 40, p-value = 0.01953 (= 10 / 512); two-sided twice that.
  const std::vector<double> x = {1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30};
  const std::vector<double> y = {0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29};
  std::vector<double> d;
  for (std::size_t i = 0; i < x.size(); ++i) d.push_back(x[i] - y[i]);
  const WilcoxonSignedRank depression = wilcoxonSignedRank(d);
  EXPECT_DOUBLE_EQ(depression.w_plus, 40.0);
  EXPECT_NEAR(*depression.p_value, 2.0 * 10.0 / 512.0, 1e-12);
  EXPECT_NEAR(*depression.p_value, exactWilcoxonByEnumeration(9, 40), 1e-12);
}

TEST(MushraStatistics, WilcoxonNormalApproximationWithTies) {
  // Ties among |d| force the approximation; computed by hand here: ranks of
  // |d| = 1,1,1,2,2,3 are 2,2,2,4.5,4.5,6; W+ = 2 + 2 + 4.5 + 6 = 14.5 (of 21).
  const std::vector<double> d = {1, -1, 1, 2, -2, 3};
  const WilcoxonSignedRank w = wilcoxonSignedRank(d);
  EXPECT_TRUE(w.ties);
  EXPECT_EQ(w.method, WilcoxonMethod::kNormalApproximation);
  EXPECT_DOUBLE_EQ(w.w_plus, 14.5);
  const double variance = 6 * 7 * 13 / 24.0 - ((27 - 3) + (8 - 2)) / 48.0;
  const double z = (14.5 - 10.5 - 0.5) / std::sqrt(variance);
  EXPECT_NEAR(*w.z, z, 1e-12);
  EXPECT_NEAR(*w.p_value, std::erfc(z / std::sqrt(2.0)), 1e-6);
}

TEST(MushraStatistics, WilcoxonStatesWhenAllDifferencesAreZero) {
  const WilcoxonSignedRank w = wilcoxonSignedRank({0, 0, 0});
  EXPECT_FALSE(w.p_value);
  EXPECT_EQ(w.zero_differences, 3u);
  EXPECT_NE(w.not_testable.find("zero"), std::string::npos) << w.not_testable;
  EXPECT_FALSE(wilcoxonSignedRank({}).p_value);
}

TEST(MushraStatistics, HolmAdjustsAKnownFamily) {
  // R: p.adjust(c(0.01, 0.04, 0.03, 0.005), "holm") = 0.03 0.06 0.06 0.02
  const auto adjusted = holmAdjust({0.01, 0.04, std::nullopt, 0.03, 0.005});
  ASSERT_EQ(adjusted.size(), 5u);
  EXPECT_NEAR(*adjusted[0], 0.03, 1e-15);
  EXPECT_NEAR(*adjusted[1], 0.06, 1e-15);
  EXPECT_FALSE(adjusted[2]);
  EXPECT_NEAR(*adjusted[3], 0.06, 1e-15);
  EXPECT_NEAR(*adjusted[4], 0.02, 1e-15);
  EXPECT_DOUBLE_EQ(*holmAdjust({0.5, 0.6})[1], 1.0);
}

TEST(MushraStatistics, PairsAreParsedOrAllNonAnchorPairs) {
  const auto pairs = parseConditionPairs("rsao:accurate,fast:accurate");
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[1].first, "fast");
  EXPECT_EQ(pairs[1].second, "accurate");
  expectInputError([] { parseConditionPairs("rsao-accurate"); }, {"'rsao-accurate'", "first:second"});
  expectInputError([] { parseConditionPairs("rsao:rsao"); }, {"itself"});
  expectInputError([] { parseConditionPairs(""); }, {"no condition pair"});

  const std::vector<MushraRating> ratings = {rating("a", "p", "reference", 5), rating("a", "p", "rsao", 3),
                                             rating("a", "p", "fast", 2), rating("a", "p", "wrong_room", 0),
                                             rating("a", "p", "accurate", 4)};
  const auto all = allConditionPairs(ratings, {"reference", "wrong_room"});
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].first + ":" + all[0].second, "rsao:fast");
  EXPECT_EQ(all[2].first + ":" + all[2].second, "fast:accurate");
}

TEST(MushraStatistics, ComparisonsPairByListenerAndPage) {
  // Rows in scrambled order; differences rsao - fast: ann p1 +1, ann p2 +2, bob p1 0, bob p2 +1.
  const std::vector<MushraRating> ratings = {
      rating("bob", "p2", "fast", 2, "music"), rating("ann", "p1", "rsao", 4),
      rating("ann", "p2", "fast", 1, "music"), rating("bob", "p1", "rsao", 3),
      rating("ann", "p1", "fast", 3),          rating("bob", "p1", "fast", 3),
      rating("ann", "p2", "rsao", 3, "music"), rating("bob", "p2", "rsao", 3, "music")};
  auto differences = pairedDifferences(ratings, "overall", {"rsao", "fast"});
  std::sort(differences.begin(), differences.end());
  EXPECT_EQ(differences, (std::vector<double>{0, 1, 1, 2}));
  const auto comparisons = comparePairs(ratings, {{"rsao", "fast"}}, 0.05);
  ASSERT_EQ(comparisons.size(), 1u);
  EXPECT_EQ(comparisons[0].t_test.n, 4u);
  EXPECT_EQ(comparisons[0].wilcoxon.zero_differences, 1u);
  EXPECT_NEAR(*comparisons[0].t_test_holm_p, *comparisons[0].t_test.p_value, 1e-15);  // a family of one
  expectInputError([&] { comparePairs(ratings, {{"rsao", "accurate"}}, 0.05); }, {"'accurate'", "no rating"});

  const auto lonely =
      comparePairs({rating("ann", "p1", "rsao", 4), rating("ann", "p1", "fast", 3)}, {{"rsao", "fast"}}, 0.05);
  EXPECT_FALSE(lonely[0].t_test.p_value);
  EXPECT_FALSE(lonely[0].t_test_holm_p);
  EXPECT_NE(lonely[0].t_test.not_testable.find("1 pair"), std::string::npos) << lonely[0].t_test.not_testable;
}

TEST(SampleStatistics, MeanAndBesselCorrectedDeviationWithClearErrors) {
  // 2, 4, 4, 4, 5, 5, 7, 9: mean 5, squared deviations sum to 32, so s = sqrt(32 / 7).
  const std::vector<double> v{2, 4, 4, 4, 5, 5, 7, 9};
  EXPECT_DOUBLE_EQ(sampleMean(v), 5.0);
  EXPECT_NEAR(sampleStandardDeviation(v), std::sqrt(32.0 / 7.0), 1e-12);
  expectInputError([] { sampleMean({}); }, {"no values"});
  expectInputError([] { sampleStandardDeviation({1.0}); }, {"at least two"});
}
