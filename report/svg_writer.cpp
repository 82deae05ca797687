#include "report/svg_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "report/base64.h"
#include "report/text_escape.h"

namespace sb::report {

std::string svgNumber(double v) {
  if (!std::isfinite(v)) v = 0;  // callers clip to the plot area; never emit "nan" into markup
  const long long tenths = std::llround(v * 10.0);
  char buffer[32];
  if (tenths % 10 == 0)
    std::snprintf(buffer, sizeof buffer, "%lld", tenths / 10);
  else
    std::snprintf(buffer, sizeof buffer, "%s%lld.%lld", tenths < 0 ? "-" : "", std::llabs(tenths) / 10,
                  std::llabs(tenths) % 10);
  return buffer;
}

namespace {

std::string strokeAttributes(const Stroke& s) {
  std::string a = " stroke=\"" + escapeXml(s.color) + "\" stroke-width=\"" + svgNumber(s.width) + "\"";
  if (!s.dash.empty()) a += " stroke-dasharray=\"" + escapeXml(s.dash) + "\"";
  if (s.opacity < 1.0) a += " stroke-opacity=\"" + formatNumber(s.opacity, 3) + "\"";
  return a;
}

std::string pointList(const std::vector<Point>& points) {
  std::string s;
  s.reserve(points.size() * 12);
  for (const auto& [x, y] : points) {
    if (!s.empty()) s += ' ';
    s += svgNumber(x);
    s += ',';
    s += svgNumber(y);
  }
  return s;
}

const char* anchorName(Anchor a) {
  switch (a) {
    case Anchor::middle: return "middle";
    case Anchor::end: return "end";
    default: return "start";
  }
}

}  // namespace

SvgWriter::SvgWriter(double width, double height, const std::string& title) : width_(width), height_(height) {
  body_ += "<title>" + escapeXml(title) + "</title>\n";
}

void SvgWriter::line(double x1, double y1, double x2, double y2, const Stroke& stroke) {
  body_ += "<line x1=\"" + svgNumber(x1) + "\" y1=\"" + svgNumber(y1) + "\" x2=\"" + svgNumber(x2) + "\" y2=\"" +
           svgNumber(y2) + "\"" + strokeAttributes(stroke) + "/>\n";
}

void SvgWriter::polyline(const std::vector<Point>& points, const Stroke& stroke) {
  if (points.size() < 2) return;
  body_ += "<polyline fill=\"none\" stroke-linejoin=\"round\"" + strokeAttributes(stroke) + " points=\"" +
           pointList(points) + "\"/>\n";
}

void SvgWriter::polygon(const std::vector<Point>& points, const std::string& fill, double opacity) {
  if (points.size() < 3) return;
  body_ += "<polygon fill=\"" + escapeXml(fill) + "\"";
  if (opacity < 1.0) body_ += " fill-opacity=\"" + formatNumber(opacity, 3) + "\"";
  body_ += " points=\"" + pointList(points) + "\"/>\n";
}

void SvgWriter::rect(double x, double y, double w, double h, const std::string& fill, const Stroke* stroke) {
  body_ += "<rect x=\"" + svgNumber(x) + "\" y=\"" + svgNumber(y) + "\" width=\"" + svgNumber(std::max(0.0, w)) +
           "\" height=\"" + svgNumber(std::max(0.0, h)) + "\" fill=\"" + escapeXml(fill) + "\"" +
           (stroke ? strokeAttributes(*stroke) : std::string()) + "/>\n";
}

void SvgWriter::image(double x, double y, double w, double h, const std::vector<unsigned char>& png) {
  body_ += "<image x=\"" + svgNumber(x) + "\" y=\"" + svgNumber(y) + "\" width=\"" + svgNumber(std::max(0.0, w)) +
           "\" height=\"" + svgNumber(std::max(0.0, h)) +
           "\" preserveAspectRatio=\"none\" style=\"image-rendering: pixelated\" href=\"data:image/png;base64," +
           base64Encode(png) + "\"/>\n";
}

void SvgWriter::circle(double cx, double cy, double r, const std::string& fill, const Stroke* stroke) {
  body_ += "<circle cx=\"" + svgNumber(cx) + "\" cy=\"" + svgNumber(cy) + "\" r=\"" + svgNumber(r) + "\" fill=\"" +
           escapeXml(fill) + "\"" + (stroke ? strokeAttributes(*stroke) : std::string()) + "/>\n";
}

void SvgWriter::text(double x, double y, const std::string& text, const TextStyle& style) {
  body_ += "<text x=\"" + svgNumber(x) + "\" y=\"" + svgNumber(y) + "\" font-size=\"" + svgNumber(style.size) +
           "\" fill=\"" + escapeXml(style.color) + "\" text-anchor=\"" + anchorName(style.anchor) + "\"";
  if (style.bold) body_ += " font-weight=\"bold\"";
  if (style.rotate != 0)
    body_ += " transform=\"rotate(" + svgNumber(style.rotate) + " " + svgNumber(x) + " " + svgNumber(y) + ")\"";
  body_ += ">" + escapeXml(text) + "</text>\n";
}

void SvgWriter::embed(double x, double y, const std::string& svgElement) {
  const std::string open = "<svg ";
  if (svgElement.compare(0, open.size(), open) != 0)
    throw std::invalid_argument("SvgWriter::embed: not an <svg> element: '" + svgElement.substr(0, 40) + "'");
  body_ += "<svg x=\"" + svgNumber(x) + "\" y=\"" + svgNumber(y) + "\" " + svgElement.substr(open.size());
  if (body_.back() != '\n') body_ += "\n";
}

void SvgWriter::beginGroup(const std::string& tooltip) {
  ++openGroups_;
  body_ += "<g>";
  if (!tooltip.empty()) body_ += "<title>" + escapeXml(tooltip) + "</title>";
  body_ += "\n";
}

void SvgWriter::endGroup() {
  if (openGroups_ == 0) throw std::logic_error("SvgWriter::endGroup without beginGroup");
  --openGroups_;
  body_ += "</g>\n";
}

std::string SvgWriter::str() const {
  if (openGroups_ != 0) throw std::logic_error("SvgWriter::str with an open group");
  const std::string w = svgNumber(width_), h = svgNumber(height_);
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" + h + "\" viewBox=\"0 0 " + w +
         " " + h + "\" font-family=\"sans-serif\" role=\"img\">\n" + body_ + "</svg>\n";
}

}  // namespace sb::report
