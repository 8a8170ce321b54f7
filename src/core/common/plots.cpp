#include "room_reverb/common/plots.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "plot_canvas.h"
#include "room_reverb/common/error.h"

namespace room_reverb::core {

namespace {

using plot_canvas::Extent;
using plot_canvas::LegendEntry;
using plot_canvas::Panel;
using plot_canvas::Swatch;

constexpr PlotColor kDarkInk{40, 40, 40};

// "<panel context>, <kind> "<label>"", or the 1-based number when there is no label.
std::string itemContext(const std::string& panel, const std::string& kind, std::size_t index,
                        const std::string& label) {
  return panel + ", " + kind + " " + (label.empty() ? std::to_string(index + 1) : "\"" + label + "\"");
}

// NaN is a missing value everywhere; infinity has no place on an axis.
void rejectInfinite(const std::vector<double>& values, const std::string& context, const std::string& name) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (std::isinf(values[k])) {
      throw InputError(context + ": " + name + "[" + std::to_string(k) + "] is " + (values[k] > 0 ? "+" : "-") +
                       "infinite (use NaN for a missing value)");
    }
  }
}

void drawLinePanel(cv::Mat& image, const cv::Rect& cell, const LinePanel& panel, const std::string& context) {
  Extent x_extent, y_extent;
  for (std::size_t s = 0; s < panel.series.size(); ++s) {
    const LineSeries& series = panel.series[s];
    const std::string where = itemContext(context, "series", s, series.label);
    if (series.x.size() != series.y.size()) {
      throw InputError(where + ": " + std::to_string(series.x.size()) + " x values but " +
                       std::to_string(series.y.size()) + " y values");
    }
    rejectInfinite(series.x, where, "x");
    rejectInfinite(series.y, where, "y");
    for (std::size_t k = 0; k < series.x.size(); ++k) {
      if (std::isnan(series.x[k]) || std::isnan(series.y[k])) continue;  // half a point is no point
      if (panel.log_x && series.x[k] <= 0.0) {
        throw InputError(where + ": x[" + std::to_string(k) + "] = " + plot_canvas::shortNumber(series.x[k]) +
                         " cannot go on a log x axis (needs x > 0)");
      }
      x_extent.add(series.x[k]);
      y_extent.add(series.y[k]);
    }
  }

  Panel canvas(image, cell, plot_canvas::chooseAxis(panel.y_range, y_extent, false, context + ", y axis"));
  canvas.setNumericX(plot_canvas::chooseAxis(panel.x_range, x_extent, panel.log_x, context + ", x axis"));
  canvas.drawGrid();
  std::vector<LegendEntry> legend;
  for (const LineSeries& series : panel.series) {
    // Each run of points between NaNs is its own stroke; a run of one point would be an
    // invisible zero-length line, so it becomes a dot.
    std::vector<cv::Point2d> run;
    const auto finish_run = [&] {
      if (run.size() == 1) canvas.circle(run.front(), 2, series.color, true);
      if (run.size() > 1) canvas.stroke(run, series.color, 2, series.dashed);
      run.clear();
    };
    for (std::size_t k = 0; k < series.x.size(); ++k) {
      if (std::isnan(series.x[k]) || std::isnan(series.y[k])) {
        finish_run();
        continue;
      }
      run.emplace_back(canvas.xPixel(series.x[k]), canvas.yPixel(series.y[k]));
    }
    finish_run();
    legend.push_back({series.label, series.color, series.dashed ? Swatch::kDashedLine : Swatch::kLine});
  }
  if (x_extent.empty()) canvas.drawNoData();
  canvas.drawFrame(panel.title, panel.x_label, panel.y_label);
  if (!x_extent.empty()) canvas.drawLegend(legend);
}

void drawBarPanel(cv::Mat& image, const cv::Rect& cell, const BarPanel& panel, const std::string& context) {
  Extent y_extent;
  y_extent.add(0.0);  // bars grow from zero, so it is always shown
  bool any_bar = false;
  for (std::size_t g = 0; g < panel.groups.size(); ++g) {
    const BarGroup& group = panel.groups[g];
    const std::string where = itemContext(context, "group", g, group.label);
    if (group.values.size() != panel.categories.size()) {
      throw InputError(where + ": " + std::to_string(group.values.size()) + " values for " +
                       std::to_string(panel.categories.size()) + " categories (one per category, NaN for none)");
    }
    rejectInfinite(group.values, where, "values");
    for (double value : group.values) {
      any_bar = any_bar || !std::isnan(value);
      y_extent.add(value);
    }
  }
  for (double line : panel.reference_lines) {
    if (!std::isfinite(line)) throw InputError(context + ": reference line at " + plot_canvas::shortNumber(line));
    y_extent.add(line);
  }

  Panel canvas(image, cell, plot_canvas::chooseAxis(panel.y_range, y_extent, false, context + ", y axis", true));
  canvas.setCategoricalX(panel.categories);
  canvas.drawGrid();
  // A category's bars share 80 % of its slot, so categories stay apart; one pixel of
  // white between neighbouring bars keeps like colours apart.
  const double band = 0.8 * canvas.slotWidth();
  const double bar = band / static_cast<double>(std::max<std::size_t>(1, panel.groups.size()));
  std::vector<LegendEntry> legend;
  for (std::size_t g = 0; g < panel.groups.size(); ++g) {
    const BarGroup& group = panel.groups[g];
    for (std::size_t c = 0; c < group.values.size(); ++c) {
      if (std::isnan(group.values[c])) continue;
      const double left = canvas.slotCenter(c) - band / 2.0 + static_cast<double>(g) * bar;
      canvas.box(left, left + std::max(0.0, bar - 2.0), 0.0, group.values[c], group.color);
    }
    legend.push_back({group.label, group.color, Swatch::kPatch});
  }
  canvas.horizontalLine(0.0, kDarkInk, false);  // the bars' base, unless it is off the range
  for (double line : panel.reference_lines) canvas.horizontalLine(line, panel.reference_color, true);
  if (!any_bar) canvas.drawNoData();
  canvas.drawFrame(panel.title, panel.x_label, panel.y_label);
  if (any_bar) canvas.drawLegend(legend);
}

// What a Tukey box shows of a non-empty set of finite values.
struct BoxStatistics {
  double q1, median, q3, mean;
  double low_whisker, high_whisker;
  std::vector<double> outliers;
};

BoxStatistics boxStatistics(const std::vector<double>& values) {
  BoxStatistics box{};
  box.q1 = quantileLinear(values, 0.25);
  box.median = quantileLinear(values, 0.5);
  box.q3 = quantileLinear(values, 0.75);
  box.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  const double reach = 1.5 * (box.q3 - box.q1);
  box.low_whisker = box.q1;
  box.high_whisker = box.q3;
  for (double value : values) {
    if (value < box.q1 - reach || value > box.q3 + reach) {
      box.outliers.push_back(value);
      continue;
    }
    // Starting from the quartiles (as matplotlib does): with few values the most extreme
    // one inside the fences can lie within the box, and a whisker must not point into it.
    box.low_whisker = std::min(box.low_whisker, value);
    box.high_whisker = std::max(box.high_whisker, value);
  }
  return box;
}

// `color` mixed with white, for box fills that the outline and median stand out on.
PlotColor tint(const PlotColor& color) {
  const auto mix = [](unsigned char channel) { return static_cast<unsigned char>(std::lround(0.3 * channel + 0.7 * 255)); };
  return {mix(color.r), mix(color.g), mix(color.b)};
}

void drawBox(const Panel& canvas, double center, double half_width, const BoxStatistics& box, const PlotColor& color) {
  const auto row = [&](double value) { return std::round(canvas.yPixel(value)); };
  const auto horizontal = [&](double value, double half, const PlotColor& ink, int thickness) {
    canvas.stroke({{center - half, row(value)}, {center + half, row(value)}}, ink, thickness, false);
  };
  canvas.stroke({{center, row(box.q3)}, {center, row(box.high_whisker)}}, color, 1, false);
  canvas.stroke({{center, row(box.q1)}, {center, row(box.low_whisker)}}, color, 1, false);
  horizontal(box.high_whisker, half_width / 2.0, color, 1);
  horizontal(box.low_whisker, half_width / 2.0, color, 1);
  canvas.box(center - half_width, center + half_width, box.q1, box.q3, tint(color));
  canvas.box(center - half_width, center + half_width, box.q1, box.q3, color, 2);
  horizontal(box.median, half_width - 2.0, kDarkInk, 2);  // inside the box's side edges
  const cv::Point2d mean(center, canvas.yPixel(box.mean));
  constexpr double kArm = 4.0;
  canvas.stroke({mean + cv::Point2d(-kArm, -kArm), mean + cv::Point2d(kArm, kArm)}, kDarkInk, 1, false);
  canvas.stroke({mean + cv::Point2d(-kArm, kArm), mean + cv::Point2d(kArm, -kArm)}, kDarkInk, 1, false);
  for (double outlier : box.outliers) canvas.circle({center, canvas.yPixel(outlier)}, 3, color, false);
}

void drawBoxPanel(cv::Mat& image, const cv::Rect& cell, const BoxPanel& panel, const std::string& context) {
  Extent y_extent;
  std::vector<std::optional<BoxStatistics>> statistics;
  std::vector<std::string> names;
  for (std::size_t b = 0; b < panel.boxes.size(); ++b) {
    const BoxSeries& series = panel.boxes[b];
    rejectInfinite(series.values, itemContext(context, "box", b, series.label), "values");
    std::vector<double> present;
    for (double value : series.values) {
      if (!std::isnan(value)) present.push_back(value);
      y_extent.add(value);
    }
    statistics.push_back(present.empty() ? std::nullopt : std::optional<BoxStatistics>(boxStatistics(present)));
    names.push_back(series.label);
  }

  Panel canvas(image, cell, plot_canvas::chooseAxis(panel.y_range, y_extent, false, context + ", y axis"));
  canvas.setCategoricalX(names);
  canvas.drawGrid();
  // Half a slot wide, but not so wide that a lone box fills the panel.
  const double half_width = std::min(0.25 * canvas.slotWidth(), 40.0);
  for (std::size_t b = 0; b < panel.boxes.size(); ++b) {
    if (!statistics[b]) continue;  // an empty box keeps its slot and name, nothing more
    drawBox(canvas, std::round(canvas.slotCenter(b)), half_width, *statistics[b], panel.boxes[b].color);
  }
  if (y_extent.empty()) canvas.drawNoData();
  canvas.drawFrame(panel.title, panel.x_label, panel.y_label);
}

// The three writers differ only in how one panel is drawn.
template <typename PanelType, typename DrawPanel>
void writeFigure(const std::string& path, const std::vector<PanelType>& panels, int columns, const std::string& who,
                 DrawPanel draw_panel) {
  plot_canvas::writePanelGrid(path, panels.size(), columns, who,
                              [&](cv::Mat& image, const cv::Rect& cell, std::size_t k) {
                                draw_panel(image, cell, panels[k], plot_canvas::panelContext(who, k, panels[k].title));
                              });
}

}  // namespace

PlotColor plotPalette(std::size_t index) {
  // matplotlib's "tab10": distinct hues of similar weight, familiar from other figures.
  static constexpr std::array<PlotColor, 10> kColors{{{31, 119, 180},
                                                      {255, 127, 14},
                                                      {44, 160, 44},
                                                      {214, 39, 40},
                                                      {148, 103, 189},
                                                      {140, 86, 75},
                                                      {227, 119, 194},
                                                      {127, 127, 127},
                                                      {188, 189, 34},
                                                      {23, 190, 207}}};
  return kColors[index % kColors.size()];
}

void writeLinePlots(const std::string& path, const std::vector<LinePanel>& panels, int columns) {
  writeFigure(path, panels, columns, "writeLinePlots", drawLinePanel);
}

void writeBarCharts(const std::string& path, const std::vector<BarPanel>& panels, int columns) {
  writeFigure(path, panels, columns, "writeBarCharts", drawBarPanel);
}

void writeBoxPlots(const std::string& path, const std::vector<BoxPanel>& panels, int columns) {
  writeFigure(path, panels, columns, "writeBoxPlots", drawBoxPanel);
}

}  // namespace room_reverb::core
