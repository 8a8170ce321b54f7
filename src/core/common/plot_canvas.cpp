#include "plot_canvas.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "room_reverb/common/error.h"

namespace room_reverb::core::plot_canvas {

namespace {

// Hershey fonts at sizes that stay legible at 100 % zoom; the title in the heavier duplex
// face so it reads as a heading.
struct TextStyle {
  int font;
  double scale;
};
constexpr TextStyle kTickText{cv::FONT_HERSHEY_SIMPLEX, 0.45};
constexpr TextStyle kLabelText{cv::FONT_HERSHEY_SIMPLEX, 0.5};
constexpr TextStyle kTitleText{cv::FONT_HERSHEY_DUPLEX, 0.6};

constexpr PlotColor kInk{40, 40, 40};
constexpr PlotColor kFrameInk{70, 70, 70};
constexpr PlotColor kGridInk{228, 228, 228};
constexpr PlotColor kFaintInk{150, 150, 150};
constexpr PlotColor kLegendBorder{200, 200, 200};
const cv::Scalar kWhite(255, 255, 255);

// Margins between a cell's edge and its plot area, in pixels. The left one grows by the
// widest y tick label; the right one leaves room for half of the last x tick label.
constexpr int kTopMargin = 40;
constexpr int kBottomMargin = 52;
constexpr int kRightMargin = 24;
constexpr int kYLabelBand = 26;
constexpr int kTickLength = 4;

// Aim for about five intervals per axis: enough to read values off, few enough that the
// labels never crowd on a 520 px panel.
constexpr double kTargetIntervals = 5.0;

// Width, and height above the baseline, of `text`.
cv::Size measure(const std::string& text, const TextStyle& style) {
  int baseline = 0;
  return cv::getTextSize(text, style.font, style.scale, 1, &baseline);
}

// `text` shortened with ".." until it is at most `max_width` pixels wide.
std::string fitText(const std::string& text, int max_width, const TextStyle& style) {
  if (measure(text, style).width <= max_width) return text;
  std::string cut = text;
  while (!cut.empty() && measure(cut + "..", style).width > max_width) cut.pop_back();
  return cut.empty() ? "" : cut + "..";
}

// For names whose end matters ("16000", "method 4"): a smaller size, down to one still
// legible, before cutting letters off.
std::pair<std::string, TextStyle> shrinkToFit(const std::string& text, int max_width, TextStyle style) {
  constexpr double kSmallestScale = 0.34;
  while (measure(text, style).width > max_width && style.scale > kSmallestScale) {
    style.scale = std::max(kSmallestScale, style.scale - 0.03);
  }
  return {fitText(text, max_width, style), style};
}

enum class HAlign { kLeft, kCenter, kRight };
enum class VAlign { kTop, kMiddle, kBaseline };

// Draws `text` so that the given side of its box sits on `anchor`.
void putAligned(cv::Mat& image, const std::string& text, cv::Point anchor, HAlign h, VAlign v,
                const TextStyle& style, const PlotColor& color) {
  const cv::Size size = measure(text, style);
  int x = anchor.x;
  if (h == HAlign::kCenter) x -= size.width / 2;
  if (h == HAlign::kRight) x -= size.width;
  int y = anchor.y;  // putText's origin is the baseline's left end
  if (v == VAlign::kTop) y += size.height;
  if (v == VAlign::kMiddle) y += size.height / 2;
  cv::putText(image, text, {x, y}, style.font, style.scale, bgr(color), 1, cv::LINE_AA);
}

// Text reading bottom to top, centred on `center`. putText cannot rotate, so the text is
// drawn on a white strip that is then turned; taking the darker pixel of strip and figure
// lays the (dark) glyphs over what is there without a white box around them.
void putVertical(cv::Mat& image, const std::string& text, cv::Point center, const TextStyle& style,
                 const PlotColor& color) {
  const cv::Size size = measure(text, style);
  cv::Mat strip(size.height + 8, size.width + 4, CV_8UC3, kWhite);
  cv::putText(strip, text, {2, size.height + 3}, style.font, style.scale, bgr(color), 1, cv::LINE_AA);
  cv::Mat turned;
  cv::rotate(strip, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  const cv::Rect target(center.x - turned.cols / 2, center.y - turned.rows / 2, turned.cols, turned.rows);
  const cv::Rect inside = target & cv::Rect(0, 0, image.cols, image.rows);
  if (inside.empty()) return;
  cv::Mat destination = image(inside);
  cv::min(destination, turned(inside - target.tl()), destination);
}

// Anti-aliased drawing takes coordinates with kShift fractional bits, so curves through
// many points do not wobble by the half pixel that rounding each point would cost.
constexpr int kShift = 4;

cv::Point subpixel(cv::Point2d point) {
  constexpr double kScale = 1 << kShift;
  return {static_cast<int>(std::lround(point.x * kScale)), static_cast<int>(std::lround(point.y * kScale))};
}

void drawLine(cv::Mat& image, cv::Point2d a, cv::Point2d b, const PlotColor& color, int thickness) {
  if (a.x == b.x || a.y == b.y) {
    // Horizontal and vertical strokes (reference lines, box edges, whiskers) on whole
    // pixels and without anti-aliasing: crisp, and in exactly their colour.
    const auto whole = [](cv::Point2d p) {
      return cv::Point(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)));
    };
    cv::line(image, whole(a), whole(b), bgr(color), thickness, cv::LINE_8);
    return;
  }
  cv::line(image, subpixel(a), subpixel(b), bgr(color), thickness, cv::LINE_AA, kShift);
}

// Liang-Barsky: the part [t0, t1] of the segment a + t (b - a), t in [0, 1], inside `box`.
// Clipping before converting to int also keeps far-off points (data outside a fixed range)
// from overflowing the pixel coordinates.
std::optional<std::pair<double, double>> clipSegment(cv::Point2d a, cv::Point2d b, const cv::Rect2d& box) {
  const cv::Point2d d = b - a;
  const double p[4] = {-d.x, d.x, -d.y, d.y};
  const double q[4] = {a.x - box.x, box.x + box.width - a.x, a.y - box.y, box.y + box.height - a.y};
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (q[k] < 0.0) return std::nullopt;  // parallel to this edge and outside it
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
  }
  if (t0 > t1) return std::nullopt;
  return std::make_pair(t0, t1);
}

// 1, 2 or 5 times a power of ten, near `raw`.
double niceStep(double raw) {
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double mantissa = raw / magnitude;
  if (mantissa < 1.5) return magnitude;
  if (mantissa < 3.0) return 2.0 * magnitude;
  if (mantissa < 7.0) return 5.0 * magnitude;
  return 10.0 * magnitude;
}

std::string formatNumber(const char* format, int precision, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, precision, value);
  return text;
}

// "2e+07" as "2e7", "5e-05" as "5e-5": narrower labels, nothing lost.
std::string compactExponent(std::string text) {
  const auto e = text.find('e');
  if (e == std::string::npos) return text;
  std::size_t digits = e + 1;
  if (text[digits] == '+') {
    text.erase(digits, 1);
  } else if (text[digits] == '-') {
    ++digits;
  }
  while (digits + 1 < text.size() && text[digits] == '0') text.erase(digits, 1);
  return text;
}

void setLinearTicks(Axis& axis) {
  const double step = niceStep((axis.hi - axis.lo) / kTargetIntervals);
  const double largest = std::max(std::abs(axis.lo), std::abs(axis.hi));
  // Plain decimals with as many places as the step needs; exponent notation where those
  // would be too long to fit beside the axis.
  const bool exponent = largest >= 1e6 || largest < 1e-3;
  const int decimals = std::clamp(static_cast<int>(-std::floor(std::log10(step) + 1e-9)), 0, 9);
  const int digits = std::clamp(static_cast<int>(std::floor(std::log10(largest)) - std::floor(std::log10(step))) + 1, 1, 15);
  const double first = std::ceil(axis.lo / step - 1e-9);
  // k * step rather than a running sum, so rounding does not pile up; capped in case the
  // range is tiny next to its magnitude.
  for (int k = 0; k < 50; ++k) {
    double value = (first + k) * step;
    if (value > axis.hi + 1e-9 * step) break;
    if (std::abs(value) < 1e-9 * step) value = 0.0;  // no "-0"
    axis.ticks.push_back(value);
    axis.labels.push_back(exponent ? compactExponent(formatNumber("%.*g", digits, value))
                                   : formatNumber("%.*f", decimals, value));
  }
}

// "2k" for 2000, "5M" for 5e6: log axes mostly carry frequencies, where that is the usual
// form, and the short labels let more ticks fit.
std::string logTickLabel(double value) {
  if (value >= 1e6 && value < 1e9) return shortNumber(value / 1e6) + "M";
  if (value >= 1e3 && value < 1e6) return shortNumber(value / 1e3) + "k";
  return shortNumber(value);
}

// Decades, with 2 and 5 between them when the axis spans few decades; every n-th decade
// when it spans many. Unlabelled minor ticks at 2..9 mark the scale as logarithmic.
void setLogTicks(Axis& axis) {
  const double lo_exponent = std::log10(axis.lo), hi_exponent = std::log10(axis.hi);
  const double decades = hi_exponent - lo_exponent;
  // Up to 3.5 decades (20 Hz..20 kHz with its margins) the 1-2-5 labels, short thanks to
  // the k and M suffixes, still fit side by side.
  const std::vector<double> mantissas = decades <= 3.5 ? std::vector<double>{1.0, 2.0, 5.0} : std::vector<double>{1.0};
  const int every = std::max(1, static_cast<int>(std::ceil(decades / 8.0)));
  const auto inside = [&](double value) { return value >= axis.lo * (1 - 1e-9) && value <= axis.hi * (1 + 1e-9); };
  for (int exponent = static_cast<int>(std::floor(lo_exponent)); exponent <= static_cast<int>(std::ceil(hi_exponent));
       ++exponent) {
    const double decade = std::pow(10.0, exponent);
    for (int m = 1; m <= 9 && decades <= 6.0; ++m) {
      if (inside(m * decade)) axis.minor_ticks.push_back(m * decade);
    }
    if (exponent % every != 0) continue;
    for (double mantissa : mantissas) {
      if (!inside(mantissa * decade)) continue;
      axis.ticks.push_back(mantissa * decade);
      axis.labels.push_back(logTickLabel(mantissa * decade));
    }
  }
  // Less than a decade or so: powers of ten alone would leave the axis nearly unlabelled.
  if (axis.ticks.size() < 3) {
    axis.ticks.clear();
    axis.labels.clear();
    setLinearTicks(axis);
  }
}

std::string rangeText(double lo, double hi) {
  return "[" + shortNumber(lo) + ", " + shortNumber(hi) + "]";
}

}  // namespace

cv::Scalar bgr(const PlotColor& color) { return cv::Scalar(color.b, color.g, color.r); }

std::string shortNumber(double value) { return formatNumber("%.*g", 6, value); }

std::string panelContext(const std::string& who, std::size_t index, const std::string& title) {
  return who + ": panel " + std::to_string(index + 1) + (title.empty() ? "" : " (\"" + title + "\")");
}

void Extent::add(double value) {
  if (!std::isfinite(value)) return;
  lo = std::min(lo, value);
  hi = std::max(hi, value);
}

double Axis::fraction(double value) const {
  if (log) return (std::log10(value) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
  return (value - lo) / (hi - lo);
}

Axis chooseAxis(const std::optional<std::pair<double, double>>& fixed, const Extent& data, bool log,
                const std::string& context, bool pin_zero) {
  Axis axis;
  axis.log = log;
  if (fixed) {
    axis.lo = fixed->first;
    axis.hi = fixed->second;
    if (!std::isfinite(axis.lo) || !std::isfinite(axis.hi) || !(axis.lo < axis.hi)) {
      throw InputError(context + ": range " + rangeText(axis.lo, axis.hi) + " must be finite and increasing");
    }
    if (log && axis.lo <= 0.0) {
      throw InputError(context + ": a log axis needs a range above 0, not " + rangeText(axis.lo, axis.hi));
    }
  } else if (data.empty()) {
    axis.lo = log ? 1.0 : 0.0;  // something to draw the frame with
    axis.hi = log ? 10.0 : 1.0;
  } else if (log) {
    double lo = std::log10(data.lo), hi = std::log10(data.hi);
    if (lo == hi) lo -= 0.5, hi += 0.5;  // a single value: the decade around it
    const double margin = 0.05 * (hi - lo);
    axis.lo = std::pow(10.0, lo - margin);
    axis.hi = std::pow(10.0, hi + margin);
  } else {
    double lo = data.lo, hi = data.hi;
    if (lo == hi) {
      // Constant data: +-10 % around it (+-1 around zero), so it sits mid-panel.
      const double half = lo == 0.0 ? 1.0 : 0.1 * std::abs(lo);
      lo -= half;
      hi += half;
    }
    const double margin = 0.05 * (hi - lo);
    axis.lo = lo - margin;
    axis.hi = hi + margin;
    if (pin_zero && data.lo == 0.0 && axis.hi > 0.0) axis.lo = 0.0;
    if (pin_zero && data.hi == 0.0 && axis.lo < 0.0) axis.hi = 0.0;
  }
  // Both ends finite but more than the largest double apart: no tick step can be found.
  if (!log && !std::isfinite(axis.hi - axis.lo)) {
    throw InputError(context + ": range " + rangeText(axis.lo, axis.hi) + " is too wide to draw");
  }
  if (log) {
    setLogTicks(axis);
  } else {
    setLinearTicks(axis);
  }
  return axis;
}

Panel::Panel(cv::Mat& image, const cv::Rect& cell, Axis y_axis) : image_(image), cell_(cell), y_(std::move(y_axis)) {
  int widest = 0;
  for (const auto& label : y_.labels) widest = std::max(widest, measure(label, kTickText).width);
  // Capped so that absurdly long labels cannot squeeze the plot area away.
  const int left = std::min(kYLabelBand + widest + kTickLength + 6, cell.width / 2);
  area_ = cv::Rect(cell.x + left, cell.y + kTopMargin, cell.width - left - kRightMargin,
                   cell.height - kTopMargin - kBottomMargin);
}

void Panel::setNumericX(Axis x_axis) { x_ = std::move(x_axis); }

void Panel::setCategoricalX(std::vector<std::string> names) {
  x_.reset();
  categories_ = std::move(names);
}

double Panel::xPixel(double x) const { return area_.x + x_->fraction(x) * (area_.width - 1); }

double Panel::yPixel(double y) const { return area_.y + (1.0 - y_.fraction(y)) * (area_.height - 1); }

double Panel::slotWidth() const {
  return static_cast<double>(area_.width) / static_cast<double>(std::max<std::size_t>(1, categories_.size()));
}

double Panel::slotCenter(std::size_t index) const { return area_.x + (static_cast<double>(index) + 0.5) * slotWidth(); }

void Panel::drawGrid() const {
  const int right = area_.x + area_.width - 1, bottom = area_.y + area_.height - 1;
  for (double tick : y_.ticks) {
    const int row = static_cast<int>(std::lround(yPixel(tick)));
    cv::line(image_, {area_.x, row}, {right, row}, bgr(kGridInk), 1, cv::LINE_8);
  }
  if (!x_) return;
  for (double tick : x_->ticks) {
    const int column = static_cast<int>(std::lround(xPixel(tick)));
    cv::line(image_, {column, area_.y}, {column, bottom}, bgr(kGridInk), 1, cv::LINE_8);
  }
}

void Panel::drawFrame(const std::string& title, const std::string& x_label, const std::string& y_label) const {
  const int bottom = area_.y + area_.height - 1;
  cv::rectangle(image_, area_, bgr(kFrameInk), 1, cv::LINE_8);

  for (std::size_t k = 0; k < y_.ticks.size(); ++k) {
    const int row = static_cast<int>(std::lround(yPixel(y_.ticks[k])));
    cv::line(image_, {area_.x - kTickLength, row}, {area_.x - 1, row}, bgr(kFrameInk), 1, cv::LINE_8);
    putAligned(image_, y_.labels[k], {area_.x - kTickLength - 4, row}, HAlign::kRight, VAlign::kMiddle, kTickText, kInk);
  }

  const int label_top = bottom + kTickLength + 5;
  if (x_) {
    for (double tick : x_->minor_ticks) {
      const int column = static_cast<int>(std::lround(xPixel(tick)));
      cv::line(image_, {column, bottom + 1}, {column, bottom + kTickLength / 2}, bgr(kFrameInk), 1, cv::LINE_8);
    }
    // Left to right, leaving out a label that would run into the one before it.
    int free_from = cell_.x;
    for (std::size_t k = 0; k < x_->ticks.size(); ++k) {
      const int column = static_cast<int>(std::lround(xPixel(x_->ticks[k])));
      cv::line(image_, {column, bottom + 1}, {column, bottom + kTickLength}, bgr(kFrameInk), 1, cv::LINE_8);
      const int width = measure(x_->labels[k], kTickText).width;
      if (column - width / 2 < free_from) continue;
      putAligned(image_, x_->labels[k], {column, label_top}, HAlign::kCenter, VAlign::kTop, kTickText, kInk);
      free_from = column + width / 2 + 8;
    }
  } else {
    const int room = static_cast<int>(slotWidth()) - 4;
    for (std::size_t k = 0; k < categories_.size(); ++k) {
      const int column = static_cast<int>(std::lround(slotCenter(k)));
      const auto [text, style] = shrinkToFit(categories_[k], room, kTickText);
      putAligned(image_, text, {column, label_top}, HAlign::kCenter, VAlign::kTop, style, kInk);
    }
  }

  const int center_x = area_.x + area_.width / 2;
  if (!x_label.empty()) {
    putAligned(image_, fitText(x_label, cell_.width - 16, kLabelText), {center_x, cell_.y + cell_.height - 10},
               HAlign::kCenter, VAlign::kBaseline, kLabelText, kInk);
  }
  if (!y_label.empty()) {
    putVertical(image_, fitText(y_label, area_.height, kLabelText),
                {cell_.x + kYLabelBand / 2 + 2, area_.y + area_.height / 2}, kLabelText, kInk);
  }
  if (!title.empty()) {
    putAligned(image_, fitText(title, cell_.width - 16, kTitleText), {center_x, cell_.y + 12}, HAlign::kCenter,
               VAlign::kTop, kTitleText, kInk);
  }
}

void Panel::drawNoData() const {
  putAligned(image_, "no data", {area_.x + area_.width / 2, area_.y + area_.height / 2}, HAlign::kCenter,
             VAlign::kMiddle, kLabelText, kFaintInk);
}

void Panel::drawLegend(const std::vector<LegendEntry>& entries) const {
  constexpr int kPadding = 6, kSwatchWidth = 24, kGap = 6, kInset = 8;
  const int row_height = measure("Ag", kTickText).height + 8;
  std::vector<LegendEntry> shown;
  for (const auto& entry : entries) {
    if (!entry.label.empty()) shown.push_back(entry);
  }
  if (shown.empty()) return;
  // At most half the plot wide, and only as many rows as fit: a legend must not hide the
  // whole plot. The last row that fits then says how many were left out.
  const int max_rows = std::max(1, (area_.height - 2 * kInset - 2 * kPadding) / row_height);
  if (static_cast<int>(shown.size()) > max_rows) {
    const std::size_t hidden = shown.size() - static_cast<std::size_t>(max_rows) + 1;
    shown.resize(static_cast<std::size_t>(max_rows) - 1);
    shown.push_back({"(" + std::to_string(hidden) + " more)", kInk, Swatch::kNone});
  }
  const int max_text = area_.width / 2 - 2 * kPadding - kSwatchWidth - kGap;
  int text_width = 0;
  for (auto& entry : shown) {
    entry.label = fitText(entry.label, max_text, kTickText);
    text_width = std::max(text_width, measure(entry.label, kTickText).width);
  }
  const cv::Size size(2 * kPadding + kSwatchWidth + kGap + text_width,
                      2 * kPadding + static_cast<int>(shown.size()) * row_height - 4);

  // Corners in order of preference; the one over the fewest data pixels wins. Data pixels
  // are those clearly darker than the grid, whatever their colour.
  const int left = area_.x + kInset, right = area_.x + area_.width - kInset - size.width;
  const int top = area_.y + kInset, lower = area_.y + area_.height - kInset - size.height;
  const cv::Point corners[] = {{right, top}, {left, top}, {right, lower}, {left, lower}};
  cv::Rect best;
  long fewest = -1;
  for (const cv::Point& corner : corners) {
    const cv::Rect candidate = cv::Rect(corner, size) & area_;
    long ink = 0;
    for (int r = candidate.y; r < candidate.y + candidate.height; ++r) {
      const auto* pixel = image_.ptr<cv::Vec3b>(r);
      for (int c = candidate.x; c < candidate.x + candidate.width; ++c) {
        if (std::min({pixel[c][0], pixel[c][1], pixel[c][2]}) < 200) ++ink;
      }
    }
    if (fewest < 0 || ink < fewest) fewest = ink, best = candidate;
  }

  cv::rectangle(image_, best, kWhite, cv::FILLED);
  cv::rectangle(image_, best, bgr(kLegendBorder), 1, cv::LINE_8);
  for (std::size_t k = 0; k < shown.size(); ++k) {
    const LegendEntry& entry = shown[k];
    const int middle = best.y + kPadding + static_cast<int>(k) * row_height + (row_height - 4) / 2;
    const int swatch_left = best.x + kPadding;
    if (entry.swatch == Swatch::kPatch) {
      cv::rectangle(image_, cv::Rect(swatch_left + 4, middle - 5, kSwatchWidth - 8, 10), bgr(entry.color), cv::FILLED);
    } else if (entry.swatch != Swatch::kNone) {
      // The swatch is a short stroke in the series' own style, dashes included.
      const std::vector<cv::Point2d> sample{{static_cast<double>(swatch_left), static_cast<double>(middle)},
                                            {static_cast<double>(swatch_left + kSwatchWidth), static_cast<double>(middle)}};
      stroke(sample, entry.color, 2, entry.swatch == Swatch::kDashedLine);
    }
    putAligned(image_, entry.label, {swatch_left + kSwatchWidth + kGap, middle}, HAlign::kLeft, VAlign::kMiddle,
               kTickText, kInk);
  }
}

void Panel::stroke(const std::vector<cv::Point2d>& points, const PlotColor& color, int thickness, bool dashed) const {
  // The pixel centres of the plot area; what reaches past them would be drawn on the frame.
  const cv::Rect2d clip(area_.x, area_.y, area_.width - 1, area_.height - 1);
  constexpr double kDash = 7.0, kPeriod = 11.0;  // on 7 px, off 4 px
  double travelled = 0.0;  // along the whole path, so the dashes run on across corners
  for (std::size_t k = 1; k < points.size(); ++k) {
    const cv::Point2d a = points[k - 1], b = points[k];
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    if (length == 0.0) continue;
    const auto part = clipSegment(a, b, clip);
    if (part && !dashed) drawLine(image_, a + part->first * (b - a), a + part->second * (b - a), color, thickness);
    if (part && dashed) {
      const double from = travelled + part->first * length, to = travelled + part->second * length;
      for (double start = std::floor(from / kPeriod) * kPeriod; start < to; start += kPeriod) {
        const double on = std::max(from, start), off = std::min(to, start + kDash);
        if (on >= off) continue;
        drawLine(image_, a + (on - travelled) / length * (b - a), a + (off - travelled) / length * (b - a), color,
                 thickness);
      }
    }
    travelled += length;
  }
}

void Panel::horizontalLine(double y, const PlotColor& color, bool dashed) const {
  const double where = y_.fraction(y);
  if (!(where >= 0.0 && where <= 1.0)) return;
  const double row = std::round(yPixel(y));
  stroke({{static_cast<double>(area_.x), row}, {static_cast<double>(area_.x + area_.width - 1), row}}, color, 1, dashed);
}

void Panel::box(double x0, double x1, double y0, double y1, const PlotColor& color, int outline) const {
  // Clamped to just outside the area first: values far beyond a fixed range would not fit
  // in an int, and the intersection below cuts the rest.
  const auto row = [&](double value) {
    const double pixel = std::clamp(yPixel(value), area_.y - 10.0, area_.y + area_.height + 10.0);
    return static_cast<int>(std::lround(pixel));
  };
  const int left = static_cast<int>(std::lround(std::min(x0, x1)));
  const int right = static_cast<int>(std::lround(std::max(x0, x1)));
  const int top = row(std::max(y0, y1)), bottom = row(std::min(y0, y1));
  const cv::Rect shape = cv::Rect(cv::Point(left, top), cv::Point(right + 1, bottom + 1)) & area_;
  if (shape.empty()) return;
  cv::rectangle(image_, shape, bgr(color), outline > 0 ? outline : cv::FILLED, cv::LINE_8);
}

void Panel::circle(cv::Point2d center, int radius, const PlotColor& color, bool filled) const {
  if (!area_.contains(cv::Point(static_cast<int>(std::floor(center.x)), static_cast<int>(std::floor(center.y))))) return;
  cv::circle(image_, subpixel(center), radius << kShift, bgr(color), filled ? cv::FILLED : 1, cv::LINE_AA, kShift);
}

void writePanelGrid(const std::string& path, std::size_t count, int columns, const std::string& who,
                    const std::function<void(cv::Mat&, const cv::Rect&, std::size_t)>& draw_panel) {
  if (count == 0) throw InputError(who + ": no panels to draw");
  if (columns < 1) throw InputError(who + ": columns must be at least 1, not " + std::to_string(columns));
  // No empty columns when there are fewer panels than columns.
  const std::size_t used_columns = std::min(count, static_cast<std::size_t>(columns));
  const std::size_t rows = (count + used_columns - 1) / used_columns;
  cv::Mat image(static_cast<int>(rows) * kPlotPanelHeight, static_cast<int>(used_columns) * kPlotPanelWidth, CV_8UC3,
                kWhite);
  for (std::size_t k = 0; k < count; ++k) {
    const cv::Rect cell(static_cast<int>(k % used_columns) * kPlotPanelWidth,
                        static_cast<int>(k / used_columns) * kPlotPanelHeight, kPlotPanelWidth, kPlotPanelHeight);
    draw_panel(image, cell, k);
  }
  // imwrite answers false for a folder it cannot write in, and throws for a name whose
  // extension names no image format; both are the caller's path.
  bool written = false;
  try {
    written = cv::imwrite(path, image);
  } catch (const cv::Exception& e) {
    throw InputError(who + ": " + path + ": cannot write the figure (" + e.err + ")");
  }
  if (!written) {
    throw InputError(who + ": " + path + ": cannot write the figure (does the folder exist, and may it be written?)");
  }
}

}  // namespace room_reverb::core::plot_canvas
