#pragma once
// The drawing shared by the line, bar and box plots (plots.cpp): numeric axes with nice
// ticks, a panel's layout, grid, frame and labels, clipped solid or dashed strokes, the
// legend, and the grid of panels written to a file. Private to plots.cpp.
#include <opencv2/core.hpp>

#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "room_reverb/common/plots.h"

namespace room_reverb::core::plot_canvas {

// OpenCV colour (BGR) of an RGB plot colour.
cv::Scalar bgr(const PlotColor& color);

// "<who>: panel <n> ("<title>")", the start of every error message about one panel.
std::string panelContext(const std::string& who, std::size_t index, const std::string& title);

// `value` in %g notation, for tick labels and messages.
std::string shortNumber(double value);

// Smallest and largest of the finite values added: NaN (missing) values are not data.
struct Extent {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double value);
  bool empty() const { return lo > hi; }
};

// A numeric axis: the range shown, linear or log10 scale, and the tick values with labels.
struct Axis {
  double lo = 0.0, hi = 1.0;
  bool log = false;
  std::vector<double> ticks;
  std::vector<std::string> labels;
  std::vector<double> minor_ticks;  // unlabelled, on a log axis
  // Where `value` lies along the axis: 0 at lo, 1 at hi.
  double fraction(double value) const;
};

// The axis shown for data of extent `data`: `fixed` when given (InputError, prefixed by
// `context`, unless finite, increasing and positive on a log axis), else the extent
// widened by 5 % on each side (in log10 on a log axis). With `pin_zero`, an extent ending
// exactly at zero keeps that end, so bars start right at the frame.
Axis chooseAxis(const std::optional<std::pair<double, double>>& fixed, const Extent& data, bool log,
                const std::string& context, bool pin_zero = false);

enum class Swatch { kLine, kDashedLine, kPatch, kNone };
struct LegendEntry {
  std::string label;
  PlotColor color;
  Swatch swatch = Swatch::kLine;
};

// One panel in its cell of the figure. The y axis is known up front because the width of
// its tick labels sets the left margin; the x axis is either numeric or a row of equally
// wide category slots. Drawing order: grid, data, frame, legend.
class Panel {
 public:
  Panel(cv::Mat& image, const cv::Rect& cell, Axis y_axis);

  void setNumericX(Axis x_axis);
  void setCategoricalX(std::vector<std::string> names);

  const cv::Rect& area() const { return area_; }  // the plot area inside the frame
  double xPixel(double x) const;                  // numeric x axis only
  double yPixel(double y) const;
  double slotCenter(std::size_t index) const;  // categorical x axis only
  double slotWidth() const;

  void drawGrid() const;
  // Frame, ticks and their labels (or the category names), axis labels and the title.
  void drawFrame(const std::string& title, const std::string& x_label, const std::string& y_label) const;
  void drawNoData() const;
  // Labelled entries only; in the corner of the plot area that covers the fewest drawn
  // data pixels (top right when that is a tie), so call it after drawing the data.
  void drawLegend(const std::vector<LegendEntry>& entries) const;

  // A polyline through `points` (pixel coordinates), clipped to the plot area; a dashed
  // one keeps its dash pattern running across the corners.
  void stroke(const std::vector<cv::Point2d>& points, const PlotColor& color, int thickness, bool dashed) const;
  // A full-width horizontal line at data value y, on a whole pixel row so it is crisp.
  void horizontalLine(double y, const PlotColor& color, bool dashed) const;
  // Filled rectangle between pixel columns x0, x1 and data values y0, y1, clipped to the
  // plot area; `outline` > 0 draws only the border that thick.
  void box(double x0, double x1, double y0, double y1, const PlotColor& color, int outline = 0) const;
  // A disc, or a ring 1 px wide, around `center` (pixel coordinates); left out when its
  // centre is outside the plot area.
  void circle(cv::Point2d center, int radius, const PlotColor& color, bool filled) const;

 private:
  cv::Mat& image_;
  cv::Rect cell_, area_;
  Axis y_;
  std::optional<Axis> x_;
  std::vector<std::string> categories_;
};

// Draws `count` panels (draw_panel(image, cell, index)) row by row in min(columns, count)
// columns and writes the figure to `path`. InputError, prefixed by `who`, for no panels,
// columns < 1, or a file that cannot be written.
void writePanelGrid(const std::string& path, std::size_t count, int columns, const std::string& who,
                    const std::function<void(cv::Mat&, const cv::Rect&, std::size_t)>& draw_panel);

}  // namespace room_reverb::core::plot_canvas
