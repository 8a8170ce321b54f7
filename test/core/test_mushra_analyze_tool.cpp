// `room_reverb mushra analyze`, run as a user runs it: results CSV files in, stats.json
// and report.md out, with the screening's exclusions and values checked against numbers
// computed here from the same ratings; bad input gives exit code 2 and one line on stderr.
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/math/special_functions/beta.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"
#include "tool_run.h"

namespace {

using room_reverb::test::expectOneLineError;
using room_reverb::test::runTool;
using room_reverb::test::tempPath;
using room_reverb::test::ToolRun;
using room_reverb::test::writeFile;

struct Row {
  std::string listener;
  int page;
  std::string content;
  std::string attribute;
  std::string condition;
  int score;
};

const std::vector<std::string> kConditions = {"reference", "rsao", "accurate", "wrong_room"};

// Four pages (2 contents x 2 attributes) per listener on the 0-5 scale: the reference at
// 5 and the wrong room at 0 (anchors identified), rsao and accurate drawn from 1..4.
// `wrong_room_score` above 0 makes the listener misidentify the low anchor on every page.
std::vector<Row> listenerRows(const std::string& listener, std::mt19937& rng, int pages = 4, int wrong_room_score = 0) {
  std::uniform_int_distribution<int> middle(1, 4);
  std::vector<Row> rows;
  for (int page = 0; page < pages; ++page) {
    const std::string content = page % 2 ? "music" : "speech";
    const std::string attribute = page < 2 ? "spatial" : "overall";
    rows.push_back({listener, page + 1, content, attribute, "reference", 5});
    rows.push_back({listener, page + 1, content, attribute, "rsao", middle(rng)});
    rows.push_back({listener, page + 1, content, attribute, "accurate", middle(rng)});
    rows.push_back({listener, page + 1, content, attribute, "wrong_room", wrong_room_score});
  }
  return rows;
}

// The standard column order, or a shuffled one with an extra column and quoted names.
std::string csvText(const std::vector<Row>& rows, bool shuffled) {
  std::ostringstream text;
  if (!shuffled)
    text << "listener,page,room,content,attribute,condition,letter,score,duration_s\n";
  else
    text << "score,\"condition\",user_agent,attribute,content,room,page,listener,duration_s,letter\n";
  for (const Row& r : rows) {
    const char letter =
        static_cast<char>('A' + (std::find(kConditions.begin(), kConditions.end(), r.condition) - kConditions.begin()));
    if (!shuffled) {
      text << r.listener << "," << r.page << ",lab," << r.content << "," << r.attribute << "," << r.condition << ","
           << letter << "," << r.score << ",7.5\n";
    } else {
      text << r.score << ",\"" << r.condition << "\",\"Mozilla/5.0 (X11, Linux)\"," << r.attribute << "," << r.content
           << ",lab," << r.page << "," << r.listener << ",7.5," << letter << "\n";
    }
  }
  return text.str();
}

nlohmann::json readJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// A results file whose one row carries `score` (for the bad-input cases).
std::string oneRowFile(const std::string& name, const std::string& score) {
  return writeFile(name,
                   "listener,page,room,content,attribute,condition,letter,score,duration_s\n"
                   "ann,1,lab,speech,overall,rsao,A," +
                       score + ",3\n");
}

}  // namespace

TEST(MushraAnalyzeTool, WritesStatisticsOfTheScreenedListeners) {
  std::mt19937 rng(2019);
  std::vector<Row> first, second;
  for (const char* name : {"ann", "bob", "cat"}) {
    const auto rows = listenerRows(name, rng);
    first.insert(first.end(), rows.begin(), rows.end());
  }
  for (const auto& rows : {listenerRows("dan", rng), listenerRows("eve", rng, 4, 5), listenerRows("fay", rng, 3)}) {
    second.insert(second.end(), rows.begin(), rows.end());
  }
  const std::string a = writeFile("mushra_tool_a.csv", csvText(first, false));
  const std::string b = writeFile("mushra_tool_b.csv", csvText(second, true));
  const auto out = tempPath("mushra_tool_out");
  const ToolRun run = runTool("mushra analyze " + a + " " + b + " --out " + out.string() + " --pairs rsao:accurate");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("kept 4 of 6 listeners"), std::string::npos) << run.out;
  const nlohmann::json stats = readJson(out / "stats.json");

  EXPECT_EQ(stats["scale"], "0-5");
  EXPECT_EQ(stats["listeners"]["total"], 6);
  EXPECT_EQ(stats["listeners"]["kept"], (std::vector<std::string>{"ann", "bob", "cat", "dan"}));
  ASSERT_EQ(stats["listeners"]["excluded"].size(), 2u);
  EXPECT_EQ(stats["listeners"]["excluded"][0]["listener"], "fay");
  EXPECT_NE(stats["listeners"]["excluded"][0]["reason"].get<std::string>().find("rated 3 of 4 pages"),
            std::string::npos);
  EXPECT_EQ(stats["listeners"]["excluded"][1]["listener"], "eve");
  EXPECT_NE(stats["listeners"]["excluded"][1]["reason"].get<std::string>().find("misidentified the anchors 4 times"),
            std::string::npos);

  // The kept listeners' "overall" scores, by hand.
  std::vector<double> rsao, differences;
  std::vector<Row> kept(first);
  for (const Row& r : second) {
    if (r.listener == "dan") kept.push_back(r);
  }
  for (const Row& r : kept) {
    if (r.attribute != "overall" || r.condition != "rsao") continue;
    rsao.push_back(r.score);
    for (const Row& other : kept) {
      if (other.listener == r.listener && other.page == r.page && other.condition == "accurate") {
        differences.push_back(r.score - other.score);
      }
    }
  }
  ASSERT_EQ(rsao.size(), 8u);
  ASSERT_EQ(differences.size(), 8u);
  double mean = 0, mean_difference = 0;
  for (double s : rsao) mean += s / 8.0;
  for (double d : differences) mean_difference += d / 8.0;
  double squares = 0;
  for (double d : differences) squares += (d - mean_difference) * (d - mean_difference);
  const double t = mean_difference / (std::sqrt(squares / 7.0) / std::sqrt(8.0));
  const double p = boost::math::ibeta(3.5, 0.5, 7.0 / (7.0 + t * t));  // two-sided p of Student's t, df = 7

  bool found_summary = false;
  for (const auto& row : stats["summaries"]) {
    if (row["attribute"] != "overall" || row["condition"] != "rsao") continue;
    found_summary = true;
    EXPECT_EQ(row["n"], 8);
    EXPECT_NEAR(row["mean"].get<double>(), mean, 1e-9);
  }
  EXPECT_TRUE(found_summary);
  EXPECT_EQ(stats["summaries_by_content"].size(), 16u);  // 2 attributes x 2 contents x 4 conditions

  ASSERT_EQ(stats["paired_tests"].size(), 2u);  // one pair on each attribute
  const auto& test = stats["paired_tests"][1];
  EXPECT_EQ(test["attribute"], "overall");
  EXPECT_EQ(test["first"], "rsao");
  EXPECT_EQ(test["second"], "accurate");
  EXPECT_EQ(test["n"], 8);
  ASSERT_TRUE(test["t_test"]["testable"].get<bool>()) << test.dump();
  EXPECT_NEAR(test["t_test"]["t"].get<double>(), t, 1e-9);
  EXPECT_NEAR(test["t_test"]["p"].get<double>(), p, 1e-6);
  EXPECT_EQ(test["t_test"]["h"], p < 0.05 ? 1 : 0);
  EXPECT_NEAR(test["t_test"]["holm_p"].get<double>(), p, 1e-6);  // one pair per attribute
  EXPECT_TRUE(test["wilcoxon"].contains("method"));

  std::ifstream report_file(out / "report.md");
  std::stringstream report;
  report << report_file.rdbuf();
  EXPECT_NE(report.str().find("| eve |"), std::string::npos);
  EXPECT_NE(report.str().find("| overall | rsao vs accurate | 8 |"), std::string::npos) << report.str();
}

TEST(MushraAnalyzeTool, Bs1534ScreeningOnTheHundredPointScale) {
  std::ostringstream text;
  text << "listener,page,room,content,attribute,condition,letter,score,duration_s\n";
  for (const std::string listener : {"ann", "bob"}) {
    for (int page = 1; page <= 4; ++page) {
      // bob rates the hidden reference 80 on 2 of 4 pages: 50 % > 15 %.
      const int reference = listener == "bob" && page <= 2 ? 80 : 98;
      text << listener << "," << page << ",lab,c" << page << ",overall,reference,A," << reference << ",5\n"
           << listener << "," << page << ",lab,c" << page << ",overall,rsao,B," << 50 + page << ",5\n"
           << listener << "," << page << ",lab,c" << page << ",overall,fast,C," << 40 + 2 * page << ",5\n"
           << listener << "," << page << ",lab,c" << page << ",overall,lowpass_3k5,D,20,5\n";
    }
  }
  const std::string file = writeFile("mushra_tool_100.csv", text.str());
  const auto out = tempPath("mushra_tool_100_out");
  const ToolRun run =
      runTool("mushra analyze " + file + " --scale 0-100 --low-anchors lowpass_3k5 --out " + out.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json stats = readJson(out / "stats.json");
  EXPECT_EQ(stats["listeners"]["kept"], (std::vector<std::string>{"ann"}));
  ASSERT_EQ(stats["listeners"]["excluded"].size(), 1u);
  EXPECT_NE(stats["listeners"]["excluded"][0]["reason"].get<std::string>().find("BS.1534-3"), std::string::npos);
  // Default pairs: the non-anchor conditions only; ann's differences rsao - fast are 9, 8, 7, 6.
  ASSERT_EQ(stats["paired_tests"].size(), 1u);
  EXPECT_EQ(stats["paired_tests"][0]["first"], "rsao");
  EXPECT_EQ(stats["paired_tests"][0]["second"], "fast");
  EXPECT_DOUBLE_EQ(stats["paired_tests"][0]["mean_difference"].get<double>(), 7.5);
  // Four untied positive differences: exact, p = 2 / 2^4.
  EXPECT_EQ(stats["paired_tests"][0]["wilcoxon"]["method"], "exact");
  EXPECT_NEAR(stats["paired_tests"][0]["wilcoxon"]["p"].get<double>(), 0.125, 1e-12);
}

TEST(MushraAnalyzeTool, BadInputEndsWithOneLine) {
  const std::string out = tempPath("mushra_tool_bad_out").string();
  const std::string missing = writeFile("mushra_missing.csv",
                                        "listener,page,room,content,attribute,condition,letter,duration_s\n"
                                        "ann,1,lab,speech,overall,rsao,A,3\n");
  expectOneLineError(runTool("mushra analyze " + missing + " --out " + out), "missing column 'score'");
  expectOneLineError(runTool("mushra analyze " + oneRowFile("mushra_high.csv", "7") + " --out " + out),
                     "outside the 0-5 scale");
  expectOneLineError(runTool("mushra analyze " + oneRowFile("mushra_word.csv", "good") + " --out " + out),
                     "score 'good' is not a number");
  expectOneLineError(runTool("mushra analyze " + writeFile("mushra_empty.csv", "") + " --out " + out),
                     "empty results file");
  expectOneLineError(runTool("mushra analyze --out " + out), "no results file given");
  expectOneLineError(runTool("mushra analyze " + oneRowFile("mushra_ok.csv", "3")), "--out DIR is required");
  expectOneLineError(runTool("mushra analyze " + oneRowFile("mushra_ok.csv", "3") + " --scale 0-10 --out " + out),
                     "unknown rating scale '0-10'");
  expectOneLineError(runTool("mushra judge --plan plan.yaml --out " + out), "available: analyze, make");
  expectOneLineError(runTool("mushra"), "analyze");

  std::mt19937 rng(7);
  const std::string good = writeFile("mushra_good.csv", csvText(listenerRows("ann", rng), false));
  expectOneLineError(runTool("mushra analyze " + good + " --pairs rsao:fast --out " + out),
                     "'fast', which no rating has");
  expectOneLineError(runTool("mushra analyze " + good + " --pairs rsao --out " + out), "first:second");
  expectOneLineError(runTool("mushra analyze " + good + " --reference hidden --out " + out), "--reference");
  expectOneLineError(runTool("mushra analyze " + good + " --alpha 2 --out " + out), "--alpha");
}
