#pragma once
// Figures as PNG files, drawn with OpenCV: line plots, grouped bar charts and Tukey box
// plots, each a grid of panels. Meant for reports of the tools (decay curves, per-band
// parameter errors, spreads over many rooms), not for interactive use.
//
// Conventions shared by the three kinds:
//  - Panels are laid out row by row in a grid of min(columns, panel count) columns; each
//    cell is kPlotPanelWidth x kPlotPanelHeight pixels on a white background.
//  - NaN is a missing value (a gap in a line, no bar, a value left out of a box);
//    +-infinity is an InputError, as it cannot be placed on an axis.
//  - Text is drawn with OpenCV's Hershey fonts, which only have ASCII glyphs: anything
//    else shows as '?'.
//  - A panel without any value to draw still gets its frame, title and "no data".
//  - Every problem with the input, and a file that cannot be written, is an InputError
//    naming the writer, the panel (1-based, with its title) and the series.
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "room_reverb/common/quantile.h"

namespace room_reverb::core {

constexpr int kPlotPanelWidth = 520;
constexpr int kPlotPanelHeight = 380;

// 8-bit RGB (not OpenCV's BGR).
struct PlotColor {
  unsigned char r = 0, g = 0, b = 0;
};

// A colour of a fixed set of ten that tell apart well on white (index wraps round).
PlotColor plotPalette(std::size_t index);

// One curve. Points are joined in the given order; a NaN x or y breaks the curve there.
// A series with an empty label is left out of the legend.
struct LineSeries {
  std::string label;
  std::vector<double> x, y;
  PlotColor color;
  bool dashed = false;
};

struct LinePanel {
  std::string title, x_label, y_label;
  std::vector<LineSeries> series;
  // Shown ranges; when empty, the data's extent plus a 5 % margin on each side. Lines
  // leaving a given range are clipped at the frame.
  std::optional<std::pair<double, double>> x_range, y_range;
  bool log_x = false;  // e.g. frequency axes; every x (and x_range) must then be > 0
};

// Axes with ticks at 1, 2, 5 x 10^k (on a log axis: decades, with 2 and 5 up to 3.5
// decades, labelled "2k", "5M" from a thousand up), a legend placed in the corner of the
// plot that hides the least of the data.
void writeLinePlots(const std::string& path, const std::vector<LinePanel>& panels, int columns = 2);

// One bar per category, side by side with the other groups' bars of that category.
struct BarGroup {
  std::string label;
  std::vector<double> values;  // one per category; NaN = no bar
  PlotColor color;
};

struct BarPanel {
  std::string title, y_label;
  std::vector<std::string> categories;  // e.g. "125", "250", ... (Hz)
  std::vector<BarGroup> groups;         // e.g. "before", "after"
  std::vector<double> reference_lines;  // horizontal dashed lines, e.g. -1 and +1 (JND)
  std::string x_label;                  // under the category names, e.g. "octave band (Hz)"
  PlotColor reference_color{110, 110, 110};
  // Shown y range; when empty it holds zero (bars grow from it), the values and the
  // reference lines, with a margin.
  std::optional<std::pair<double, double>> y_range;
};

void writeBarCharts(const std::string& path, const std::vector<BarPanel>& panels, int columns = 2);

// One box over `values` (NaN values are left out), named by `label` under it.
struct BoxSeries {
  std::string label;
  std::vector<double> values;
  PlotColor color;
};

struct BoxPanel {
  std::string title, y_label;
  std::vector<BoxSeries> boxes;
  std::optional<std::pair<double, double>> y_range;  // automatic (with a margin) when empty
  std::string x_label;
};

// Tukey box plots: the box spans the first to the third quartile (quantileLinear), with a
// line at the median; whiskers reach the most extreme values within 1.5 interquartile
// ranges of the box; values beyond are outliers, drawn as circles; the mean is a small
// cross.
void writeBoxPlots(const std::string& path, const std::vector<BoxPanel>& panels, int columns = 2);

}  // namespace room_reverb::core
