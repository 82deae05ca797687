#pragma once
// A minimal SVG writer: shapes, text and groups appended to one <svg> element. Every string is escaped;
// coordinates are user units (pixels at 100% zoom) rounded to 0.1 to keep long polylines small.

#include <string>
#include <utility>
#include <vector>

namespace sb::report {

using Point = std::pair<double, double>;

struct Stroke {
  Stroke(std::string colour = "#000000", double strokeWidth = 1.0, std::string dashArray = "", double alpha = 1.0)
      : color(std::move(colour)), width(strokeWidth), dash(std::move(dashArray)), opacity(alpha) {}
  std::string color;
  double width;
  std::string dash;  // SVG dash array, e.g. "4 3"; empty = solid
  double opacity;
};

enum class Anchor { start, middle, end };

struct TextStyle {
  double size = 12;             // px
  Anchor anchor = Anchor::start;
  std::string color = "#222222";
  bool bold = false;
  double rotate = 0;            // degrees, about the text's anchor point
};

class SvgWriter {
 public:
  // `title` becomes the <title> child (the accessible name, also shown as a tooltip).
  SvgWriter(double width, double height, const std::string& title);

  void line(double x1, double y1, double x2, double y2, const Stroke& stroke);
  // An open polyline; fewer than two points draws nothing.
  void polyline(const std::vector<Point>& points, const Stroke& stroke);
  void polygon(const std::vector<Point>& points, const std::string& fill, double opacity = 1.0);
  void rect(double x, double y, double w, double h, const std::string& fill, const Stroke* stroke = nullptr);
  void circle(double cx, double cy, double r, const std::string& fill, const Stroke* stroke = nullptr);
  void text(double x, double y, const std::string& text, const TextStyle& style = {});
  // A PNG embedded as a data: URI, stretched over the box with its pixels kept sharp (maps).
  void image(double x, double y, double w, double h, const std::vector<unsigned char>& png);
  // Places a complete <svg> element (e.g. a plot from plots.h) with its top-left corner at (x, y), nested as
  // is (several plots in one .svg file). Throws std::invalid_argument when `svgElement` is not an <svg>.
  void embed(double x, double y, const std::string& svgElement);
  // Wraps the following elements in <g>; `tooltip` (optional) becomes its <title>. Must be balanced.
  void beginGroup(const std::string& tooltip = "");
  void endGroup();

  double width() const { return width_; }
  double height() const { return height_; }
  // The complete <svg> element. Throws std::logic_error if a group is still open.
  std::string str() const;

 private:
  double width_, height_;
  int openGroups_ = 0;
  std::string body_;
};

// Rounds to 0.1 and prints without trailing zeros ("12", "12.5").
std::string svgNumber(double v);

}  // namespace sb::report
