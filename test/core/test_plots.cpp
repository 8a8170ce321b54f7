#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "test_files.h"
#include "room_reverb/common/error.h"
#include "room_reverb/common/plots.h"

using namespace room_reverb::core;

namespace {

using room_reverb::test::expectInputError;
using room_reverb::test::tempPath;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Colours no axis, grid or text pixel has, so counting them counts only the data.
constexpr PlotColor kRed{200, 30, 60};
constexpr PlotColor kBlue{20, 90, 210};
constexpr PlotColor kMagenta{230, 0, 230};

cv::Mat readBack(const std::string& path) {
  cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  EXPECT_FALSE(image.empty()) << path;
  return image;
}

bool isColor(const cv::Vec3b& pixel, const PlotColor& color) {
  return pixel[2] == color.r && pixel[1] == color.g && pixel[0] == color.b;
}

// Pixels of exactly `color` in each row of `image`.
std::vector<int> colorPerRow(const cv::Mat& image, const PlotColor& color) {
  std::vector<int> counts(static_cast<std::size_t>(image.rows), 0);
  for (int r = 0; r < image.rows; ++r) {
    for (int c = 0; c < image.cols; ++c) counts[static_cast<std::size_t>(r)] += isColor(image.at<cv::Vec3b>(r, c), color);
  }
  return counts;
}

int countColor(const cv::Mat& image, const PlotColor& color) {
  int total = 0;
  for (int count : colorPerRow(image, color)) total += count;
  return total;
}

int countNonWhite(const cv::Mat& image) {
  return static_cast<int>(image.total()) - countColor(image, PlotColor{255, 255, 255});
}

// The row with the most pixels of `color`.
int busiestRow(const cv::Mat& image, const PlotColor& color) {
  const auto counts = colorPerRow(image, color);
  return static_cast<int>(std::max_element(counts.begin(), counts.end()) - counts.begin());
}

// Runs of `color` along row `row`, and the widest stretch between two of them.
struct Runs {
  int count = 0;
  int widest_gap = 0;
};
Runs runsAlongRow(const cv::Mat& image, int row, const PlotColor& color) {
  Runs runs;
  int last_end = -1;
  bool inside = false;
  for (int c = 0; c < image.cols; ++c) {
    const bool hit = isColor(image.at<cv::Vec3b>(row, c), color);
    if (hit && !inside) {
      ++runs.count;
      if (last_end >= 0) runs.widest_gap = std::max(runs.widest_gap, c - last_end);
    }
    if (!hit && inside) last_end = c;
    inside = hit;
  }
  return runs;
}

LineSeries series(const std::string& label, std::vector<double> x, std::vector<double> y, PlotColor color,
                  bool dashed = false) {
  LineSeries s;
  s.label = label;
  s.x = std::move(x);
  s.y = std::move(y);
  s.color = color;
  s.dashed = dashed;
  return s;
}

LinePanel decayPanel() {
  LinePanel panel;
  panel.title = "Energy decay";
  panel.x_label = "time (s)";
  panel.y_label = "level (dB)";
  std::vector<double> t, measured, fitted;
  for (int k = 0; k <= 100; ++k) {
    t.push_back(0.01 * k);
    measured.push_back(-60.0 * 0.01 * k + 3.0 * std::sin(0.7 * k));
    fitted.push_back(-60.0 * 0.01 * k);
  }
  panel.series.push_back(series("measured", t, measured, kRed));
  panel.series.push_back(series("fit", t, fitted, kBlue, true));
  return panel;
}

BarPanel bandPanel() {
  BarPanel panel;
  panel.title = "T30 error per band";
  panel.y_label = "error (JND)";
  panel.x_label = "octave band (Hz)";
  panel.categories = {"125", "250", "500", "1k", "2k", "4k"};
  panel.groups = {{"before", {2.5, 1.8, -0.4, 0.9, -1.6, 3.1}, kRed}, {"after", {0.6, -0.3, 0.2, kNaN, -0.5, 0.8}, kBlue}};
  panel.reference_lines = {-1.0, 1.0};
  panel.reference_color = kMagenta;
  return panel;
}

BoxPanel spreadPanel() {
  BoxPanel panel;
  panel.title = "C50 error over rooms";
  panel.y_label = "error (dB)";
  panel.boxes = {{"before", {-3.1, -1.2, 0.4, 0.8, 1.9, 2.2, 2.5, 9.0}, kRed}, {"after", {-0.6, -0.2, 0.1, 0.3, 0.5}, kBlue}};
  return panel;
}

TEST(QuantileLinear, MatchesHandComputedValues) {
  EXPECT_DOUBLE_EQ(quantileLinear({1, 2, 3, 4}, 0.25), 1.75);  // position 0.75 between 1 and 2
  EXPECT_DOUBLE_EQ(quantileLinear({1, 2, 3, 4}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(quantileLinear({1, 2, 3, 4}, 0.75), 3.25);
  EXPECT_DOUBLE_EQ(quantileLinear({1, 2, 3, 4}, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(quantileLinear({1, 2, 3, 4}, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(quantileLinear({4, 1, 3, 2}, 0.25), 1.75);  // order does not matter
  EXPECT_DOUBLE_EQ(quantileLinear({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 0.9), 9.1);  // position 8.1
  EXPECT_DOUBLE_EQ(quantileLinear({-2, 10, 0}, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(quantileLinear({7}, 0.3), 7.0);
}

TEST(QuantileLinear, RejectsBadInput) {
  expectInputError([] { quantileLinear({}, 0.5); }, {"no values"});
  expectInputError([] { quantileLinear({1, 2}, 1.5); }, {"q = 1.5", "[0, 1]"});
  expectInputError([] { quantileLinear({1, 2}, kNaN); }, {"outside [0, 1]"});
  expectInputError([] { quantileLinear({1, kNaN}, 0.5); }, {"value 1"});
}

TEST(LinePlots, ImageHasTheGridSizeAndShowsEverySeries) {
  const std::string path = tempPath("lines.png").string();
  LinePanel unlabelled = decayPanel();
  unlabelled.title = "no legend";
  unlabelled.series = {series("", {0, 1, 2}, {5, 1, 4}, kMagenta)};  // not in a legend: drawn or nothing
  writeLinePlots(path, {decayPanel(), decayPanel(), unlabelled}, 2);

  const cv::Mat image = readBack(path);
  EXPECT_EQ(image.cols, 2 * kPlotPanelWidth);
  EXPECT_EQ(image.rows, 2 * kPlotPanelHeight);  // three panels in two columns: two rows
  EXPECT_GT(countNonWhite(image), 20000);
  // A legend swatch is 24 x 2 pixels; the curves themselves are hundreds.
  EXPECT_GT(countColor(image, kRed), 400);
  EXPECT_GT(countColor(image, kBlue), 300);
  EXPECT_GT(countColor(image, kMagenta), 100);
}

TEST(LinePlots, FewerPanelsThanColumnsLeaveNoEmptyColumns) {
  const std::string path = tempPath("one_line_panel.png").string();
  writeLinePlots(path, {decayPanel()}, 3);
  const cv::Mat image = readBack(path);
  EXPECT_EQ(image.cols, kPlotPanelWidth);
  EXPECT_EQ(image.rows, kPlotPanelHeight);
}

TEST(LinePlots, NaNBreaksTheLine) {
  const std::string path = tempPath("gap.png").string();
  LinePanel panel;
  panel.series = {series("level", {0, 1, 2, 3, 4, 5, 6, 7, 8}, {2, 2, 2, 2, kNaN, 2, 2, 2, 2}, kRed)};
  panel.y_range = std::make_pair(0.0, 4.0);
  writeLinePlots(path, {panel});
  const cv::Mat image = readBack(path);
  const Runs runs = runsAlongRow(image, busiestRow(image, kRed), kRed);
  // Points 3 and 5 are not joined: two eighths of the ~450 px wide axis stay empty.
  EXPECT_EQ(runs.count, 2);
  EXPECT_GT(runs.widest_gap, 80);
}

TEST(LinePlots, ConstantDataSitsMidPanel) {
  const std::string path = tempPath("constant.png").string();
  LinePanel panel;
  panel.series = {series("flat", {0, 1, 2, 3}, {-12, -12, -12, -12}, kRed)};
  writeLinePlots(path, {panel});
  const cv::Mat image = readBack(path);
  const int row = busiestRow(image, kRed);
  EXPECT_GT(countColor(image, kRed), 300);
  EXPECT_GT(row, kPlotPanelHeight / 3);
  EXPECT_LT(row, 2 * kPlotPanelHeight / 3);
}

TEST(LinePlots, LogFrequencyAxisAndDashedSeries) {
  const std::string path = tempPath("log.png").string();
  LinePanel panel;
  panel.title = "Absorption";
  panel.x_label = "frequency (Hz)";
  panel.log_x = true;
  panel.series = {series("panel", {63, 125, 250, 500, 1000, 2000, 4000, 8000, 16000},
                         {0.3, 0.3, 0.35, 0.5, 0.6, 0.6, 0.6, 0.6, 0.6}, kBlue, true)};
  writeLinePlots(path, {panel});
  const cv::Mat image = readBack(path);
  EXPECT_GT(countColor(image, kBlue), 150);
}

TEST(LinePlots, EmptySeriesDrawAnEmptyPanel) {
  const std::string path = tempPath("empty_lines.png").string();
  LinePanel nothing;
  nothing.title = "nothing";
  LinePanel all_missing;
  all_missing.series = {series("missing", {kNaN, kNaN}, {1, 2}, kRed), series("empty", {}, {}, kBlue)};
  writeLinePlots(path, {nothing, all_missing});
  const cv::Mat image = readBack(path);
  EXPECT_EQ(image.cols, 2 * kPlotPanelWidth);
  EXPECT_GT(countNonWhite(image), 1000);  // frames, ticks, "no data"
  EXPECT_EQ(countColor(image, kRed), 0);  // and no legend for data that is not there
}

TEST(LinePlots, RejectsBadInput) {
  const std::string path = tempPath("bad_lines.png").string();
  expectInputError([&] { writeLinePlots(path, {}); }, {"writeLinePlots", "no panels"});
  expectInputError([&] { writeLinePlots(path, {decayPanel()}, 0); }, {"columns"});

  LinePanel uneven;
  uneven.title = "uneven";
  uneven.series = {series("a", {1, 2, 3}, {1, 2}, kRed)};
  expectInputError([&] { writeLinePlots(path, {decayPanel(), uneven}); },
                   {"panel 2", "\"uneven\"", "series \"a\"", "3 x values but 2 y values"});

  LinePanel infinite;
  infinite.series = {series("a", {1, 2, 3}, {1, kInf, 2}, kRed)};
  expectInputError([&] { writeLinePlots(path, {infinite}); }, {"y[1]", "infinite"});

  LinePanel log_zero;
  log_zero.log_x = true;
  log_zero.series = {series("a", {0, 10, 100}, {1, 2, 3}, kRed)};
  expectInputError([&] { writeLinePlots(path, {log_zero}); }, {"x[0]", "log x axis"});

  LinePanel reversed = decayPanel();
  reversed.y_range = std::make_pair(0.0, -60.0);
  expectInputError([&] { writeLinePlots(path, {reversed}); }, {"y axis", "increasing"});

  expectInputError([&] { writeLinePlots(tempPath("no_such_folder/lines.png").string(), {decayPanel()}); },
                   {"no_such_folder/lines.png", "cannot write"});
  expectInputError([&] { writeLinePlots(tempPath("lines.not_an_image").string(), {decayPanel()}); },
                   {"lines.not_an_image", "cannot write"});
}

TEST(BarCharts, ImageHasTheGridSizeBarsAndDashedReferenceLines) {
  const std::string path = tempPath("bars.png").string();
  writeBarCharts(path, {bandPanel(), bandPanel()}, 1);

  const cv::Mat image = readBack(path);
  EXPECT_EQ(image.cols, kPlotPanelWidth);
  EXPECT_EQ(image.rows, 2 * kPlotPanelHeight);
  EXPECT_GT(countNonWhite(image), 20000);
  EXPECT_GT(countColor(image, kRed), 2000);
  EXPECT_GT(countColor(image, kBlue), 500);
  // The reference lines: rows of magenta broken into many dashes.
  const int row = busiestRow(image, kMagenta);
  EXPECT_GT(colorPerRow(image, kMagenta)[static_cast<std::size_t>(row)], 150);
  const Runs dashes = runsAlongRow(image, row, kMagenta);
  EXPECT_GT(dashes.count, 20);
  EXPECT_LT(dashes.widest_gap, 40);  // breaks are dash gaps (or a bar drawn over), not missing line
}

TEST(BarCharts, EmptyPanelsAndMissingBars) {
  const std::string path = tempPath("empty_bars.png").string();
  BarPanel nothing;
  nothing.title = "no groups";
  BarPanel all_missing = bandPanel();
  all_missing.groups = {{"none", std::vector<double>(6, kNaN), kRed}};
  all_missing.reference_lines.clear();
  writeBarCharts(path, {nothing, all_missing});
  const cv::Mat image = readBack(path);
  EXPECT_EQ(image.cols, 2 * kPlotPanelWidth);
  EXPECT_GT(countNonWhite(image), 1000);
  EXPECT_EQ(countColor(image, kRed), 0);
}

TEST(BarCharts, RejectsBadInput) {
  const std::string path = tempPath("bad_bars.png").string();
  expectInputError([&] { writeBarCharts(path, {}); }, {"writeBarCharts", "no panels"});
  BarPanel short_group = bandPanel();
  short_group.groups[1].values.pop_back();
  expectInputError([&] { writeBarCharts(path, {short_group}); }, {"group \"after\"", "5 values for 6 categories"});
  BarPanel infinite = bandPanel();
  infinite.groups[0].values[2] = -kInf;
  expectInputError([&] { writeBarCharts(path, {infinite}); }, {"values[2]", "infinite"});
  BarPanel bad_line = bandPanel();
  bad_line.reference_lines.push_back(kNaN);
  expectInputError([&] { writeBarCharts(path, {bad_line}); }, {"reference line"});
  expectInputError([&] { writeBarCharts(tempPath("no_such_folder/bars.png").string(), {bandPanel()}); },
                   {"cannot write"});
}

TEST(BoxPlots, ImageHasTheGridSizeAndEveryBox) {
  const std::string path = tempPath("boxes.png").string();
  writeBoxPlots(path, {spreadPanel(), spreadPanel(), spreadPanel()}, 3);
  const cv::Mat image = readBack(path);
  EXPECT_EQ(image.cols, 3 * kPlotPanelWidth);
  EXPECT_EQ(image.rows, kPlotPanelHeight);
  EXPECT_GT(countNonWhite(image), 20000);
  EXPECT_GT(countColor(image, kRed), 300);
  EXPECT_GT(countColor(image, kBlue), 300);
}

TEST(BoxPlots, BoxesSpanTheQuartiles) {
  // Quartiles 2 and 8 for one box, 4 and 6 for the other: on the same axis the first box
  // is three times as tall. Its horizontal edges are the only long rows of its colour
  // (whisker caps are half as wide).
  const std::string path = tempPath("quartiles.png").string();
  BoxPanel panel;
  panel.boxes = {{"wide", {2, 2, 8, 8}, kRed}, {"narrow", {4, 4, 6, 6}, kBlue}};
  panel.y_range = std::make_pair(0.0, 10.0);
  writeBoxPlots(path, {panel});
  const cv::Mat image = readBack(path);
  const auto height = [&](const PlotColor& color) {
    const auto counts = colorPerRow(image, color);
    int top = -1, bottom = -1;
    for (int r = 0; r < image.rows; ++r) {
      if (counts[static_cast<std::size_t>(r)] < 60) continue;
      if (top < 0) top = r;
      bottom = r;
    }
    return bottom - top;
  };
  ASSERT_GT(height(kBlue), 20);
  EXPECT_NEAR(static_cast<double>(height(kRed)) / height(kBlue), 3.0, 0.1);
}

TEST(BoxPlots, EmptyBoxesAndConstantValues) {
  const std::string path = tempPath("empty_boxes.png").string();
  BoxPanel nothing;
  nothing.title = "no boxes";
  BoxPanel empty_box;
  empty_box.boxes = {{"none", {}, kRed}, {"missing", {kNaN}, kRed}};
  BoxPanel constant;
  constant.boxes = {{"same", {3, 3, 3}, kBlue}};
  writeBoxPlots(path, {nothing, empty_box, constant}, 2);
  const cv::Mat image = readBack(path);
  EXPECT_EQ(image.rows, 2 * kPlotPanelHeight);
  EXPECT_EQ(countColor(image, kRed), 0);
  EXPECT_GT(countColor(image, kBlue), 0);  // the flat box's ends show beside the median
}

TEST(BoxPlots, RejectsBadInput) {
  const std::string path = tempPath("bad_boxes.png").string();
  expectInputError([&] { writeBoxPlots(path, {}); }, {"writeBoxPlots", "no panels"});
  BoxPanel infinite = spreadPanel();
  infinite.boxes[1].values.push_back(kInf);
  expectInputError([&] { writeBoxPlots(path, {infinite}); }, {"box \"after\"", "values[5]", "infinite"});
  expectInputError([&] { writeBoxPlots(tempPath("no_such_folder/boxes.png").string(), {spreadPanel()}); },
                   {"cannot write"});
}

}  // namespace
