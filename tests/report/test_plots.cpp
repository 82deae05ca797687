// Plot building blocks: nice axes, escaping, SVG plots (well-formed, escaped, gaps, equal aspect, bars),
// base64, the PNG codec and the map difference.

#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "report/axis.h"
#include "report/base64.h"
#include "report/map_difference.h"
#include "report/plots.h"
#include "report/png_codec.h"
#include "report/svg_writer.h"
#include "report/text_escape.h"
#include "tests/report/markup_check.h"

using namespace sb::report;
using sb::test::checkMarkup;

namespace {

std::vector<std::pair<double, double>> parsePoints(const std::string& points) {
  std::vector<std::pair<double, double>> out;
  std::istringstream in(points);
  std::string pair;
  while (in >> pair) {
    const size_t comma = pair.find(',');
    out.emplace_back(std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1)));
  }
  return out;
}

}  // namespace

TEST_CASE("nice axes use 1-2-5 steps, cover the data and label without -0", "[report]") {
  const Axis a = niceAxis(0, 9.3, 6);
  CHECK(a.min == 0);
  CHECK(a.max == 10);
  CHECK(a.step == 2);
  CHECK(a.labels == std::vector<std::string>{"0", "2", "4", "6", "8", "10"});

  const Axis b = niceAxis(-0.013, 0.021, 5);
  CHECK(b.step == Approx(0.01));
  CHECK(b.min == Approx(-0.02));
  CHECK(b.max == Approx(0.03));
  CHECK(b.labels == std::vector<std::string>{"-0.02", "-0.01", "0", "0.01", "0.02", "0.03"});

  const Axis flat = niceAxis(5, 5);
  CHECK(flat.min < 5);
  CHECK(flat.max > 5);
  const Axis bad = niceAxis(std::nan(""), 1);
  CHECK(bad.min == 0);
  CHECK(bad.max == 1);

  const Axis within = ticksWithin(0.13, 0.71, 0.2);
  CHECK(within.labels == std::vector<std::string>{"0.2", "0.4", "0.6"});
  CHECK(tickLabel(-1e-17, 0.5) == "0");
  CHECK(niceNumber(0.6, true) == Approx(0.5));
  CHECK(niceNumber(0.6, false) == Approx(1.0));
}

TEST_CASE("text is escaped for markup and numbers print compactly", "[report]") {
  CHECK(escapeXml("<a href=\"x\">Tom & Jerry's</a>") == "&lt;a href=&quot;x&quot;&gt;Tom &amp; Jerry&#39;s&lt;/a&gt;");
  CHECK(escapeXml(std::string("bell\x07")) == "bell\xEF\xBF\xBD");
  CHECK(formatNumber(0.1 + 0.2) == "0.3");
  CHECK(formatNumber(-0.0) == "0");
  CHECK(formatNumber(1234567.0, 4) == "1.235e+06");
  CHECK(formatNumber(std::nan("")) == "nan");
}

TEST_CASE("line plots are well-formed SVG with escaped text, legends and gaps at NaN", "[report]") {
  LinePlot p;
  p.title = "ITE < 5 cm & \"tracked\"";
  p.xLabel = "frame";
  p.yLabel = "cm";
  const double nan = std::nan("");
  p.series.push_back({"aligned", {0, 1, 2, 3, 4, 5}, {1, 2, nan, 2, 3, 1}, "", LineStyle::line, 1.5, false});
  p.series.push_back({"knob <csr>", {0, 1, 2, 3, 4, 5}, {1, 1, 2, 2, 4, 4}, "#123456", LineStyle::step, 1.5, true});
  p.events.push_back({"surface", {1, 4}, ""});
  const std::string svg = svgLinePlot(p);
  const auto check = checkMarkup(svg);
  INFO(svg);
  REQUIRE(check.errors.empty());
  CHECK(check.find("svg").size() == 1);
  CHECK(check.find("title").front()->text == p.title);
  // The NaN splits the first series into two polylines; the second is one step line.
  CHECK(check.find("polyline").size() == 3);
  bool legend = false;
  for (const auto* t : check.find("text")) legend |= t->text == "knob <csr>";
  CHECK(legend);
  // Step style: consecutive points share x or y.
  for (const auto* poly : check.find("polyline")) {
    if (poly->attributes.at("stroke") != "#123456") continue;
    const auto pts = parsePoints(poly->attributes.at("points"));
    for (size_t i = 1; i < pts.size(); ++i) CHECK((pts[i].first == pts[i - 1].first || pts[i].second == pts[i - 1].second));
  }
  // Event marks: one short line per event in the lane colour.
  size_t marks = 0;
  for (const auto* line : check.find("line")) marks += line->attributes.at("stroke") == paletteColour(1);
  CHECK(marks >= 2);
}

TEST_CASE("stacked plots fill one polygon per series, the last reaching the sum", "[report]") {
  LinePlot p;
  p.stacked = true;
  p.series.push_back({"a", {0, 1, 2}, {1, 1, 1}, "", LineStyle::line, 1, false});
  p.series.push_back({"b", {0, 1, 2}, {2, 3, 4}, "", LineStyle::line, 1, false});
  const auto check = checkMarkup(svgLinePlot(p));
  REQUIRE(check.errors.empty());
  REQUIRE(check.find("polygon").size() == 2);
  // The y axis reaches at least the top of the stack (5).
  bool hasFive = false;
  for (const auto* t : check.find("text")) hasFive |= t->text == "5";
  CHECK(hasFive);
}

TEST_CASE("XY plots keep equal aspect: one metre spans as many pixels on both axes", "[report]") {
  XyPlot p;
  p.series.push_back({"path", {0, 4, 4, 0, 0}, {0, 0, 1, 1, 0}, "", LineStyle::line, 1.5, false});
  p.size = {600, 500};
  const auto check = checkMarkup(svgXyPlot(p));
  REQUIRE(check.errors.empty());
  REQUIRE(check.find("polyline").size() == 1);
  const auto pts = parsePoints(check.find("polyline").front()->attributes.at("points"));
  REQUIRE(pts.size() == 5);
  const double width = std::fabs(pts[1].first - pts[0].first), height = std::fabs(pts[2].second - pts[1].second);
  CHECK(width / height == Approx(4.0).epsilon(0.01));
  CHECK(pts[2].second < pts[1].second);  // y grows upwards on screen
  CHECK(check.find("circle").size() == 2);  // start ring + legend ring
}

TEST_CASE("bar charts draw one bar per finite value with value labels", "[report]") {
  BarChart c;
  c.title = "ms per frame";
  c.categories = {"lr0", "lr1", "a very long sequence name that needs rotating"};
  c.groups.push_back({"DEFAULT", {10, 20, 30}, ""});
  c.groups.push_back({"SLAMBooster", {3, std::nan(""), 9}, ""});
  const auto check = checkMarkup(svgBarChart(c));
  REQUIRE(check.errors.empty());
  size_t bars = 0;
  for (const auto* r : check.find("rect"))
    bars += r->attributes.at("fill") == paletteColour(0) || r->attributes.at("fill") == paletteColour(1);
  CHECK(bars == 5 + 2);  // five bars plus the two legend swatches
  bool rotated = false;
  for (const auto* t : check.find("text")) rotated |= t->attributes.count("transform") > 0;
  CHECK(rotated);
}

TEST_CASE("a bar chart's limit is a dashed line inside the y range, with a legend entry", "[report]") {
  BarChart c;
  c.title = "ATE";
  c.categories = {"lr0"};
  c.groups.push_back({"SLAMBooster", {2}, ""});
  c.limit = 5.0;
  c.limitName = "5 cm bound";
  const auto check = checkMarkup(svgBarChart(c));
  REQUIRE(check.errors.empty());
  size_t dashedLines = 0;
  for (const auto* l : check.find("line")) dashedLines += l->attributes.count("stroke-dasharray") > 0;
  CHECK(dashedLines == 2);  // the line and its legend swatch
  bool legend = false;
  for (const auto* t : check.find("text")) legend |= t->text == "5 cm bound";
  CHECK(legend);
  // On the bars' scale: the bar of 2 is 0.4 of the way from the axis to the line at 5.
  double barTop = 0, barBottom = 0, limitY = 0;
  for (const auto* r : check.find("rect"))
    if (r->attributes.at("fill") == paletteColour(0) && std::stod(r->attributes.at("height")) > 20) {
      barTop = std::stod(r->attributes.at("y"));
      barBottom = barTop + std::stod(r->attributes.at("height"));
    }
  for (const auto* l : check.find("line"))
    if (l->attributes.count("stroke-dasharray") && l->attributes.at("stroke") == "#CC0000")
      limitY = std::max(limitY, std::stod(l->attributes.at("y1")));  // the legend swatch sits higher
  REQUIRE(barBottom > barTop);
  CHECK((barBottom - barTop) / (barBottom - limitY) == Approx(0.4).margin(0.01));
}

TEST_CASE("SvgWriter::embed nests complete plots at an offset and rejects other markup", "[report]") {
  LinePlot p;
  p.title = "ITE";
  p.series.push_back({"ITE", {0, 1, 2}, {1, 2, 1}});
  SvgWriter svg(820, 520, "stack");
  svg.embed(0, 0, svgLinePlot(p));
  svg.embed(0, 260, svgLinePlot(p));
  const auto check = checkMarkup(svg.str());
  REQUIRE(check.errors.empty());
  const auto nested = check.find("svg");
  REQUIRE(nested.size() == 3);  // closing order: the two plots, then the outer one
  CHECK(nested[1]->attributes.at("y") == "260");
  CHECK(nested[2]->attributes.count("y") == 0);
  CHECK_THROWS_AS(svg.embed(0, 0, "<g/>"), std::invalid_argument);
}

TEST_CASE("base64 follows RFC 4648 and rejects malformed input", "[report]") {
  auto enc = [](const std::string& s) { return base64Encode(std::vector<uint8_t>(s.begin(), s.end())); };
  CHECK(enc("") == "");
  CHECK(enc("f") == "Zg==");
  CHECK(enc("fo") == "Zm8=");
  CHECK(enc("foo") == "Zm9v");
  CHECK(enc("foobar") == "Zm9vYmFy");
  std::vector<uint8_t> bytes;
  REQUIRE(base64Decode("Zm9vYg==", bytes));
  CHECK(std::string(bytes.begin(), bytes.end()) == "foob");
  CHECK_FALSE(base64Decode("Zm9=vYg=", bytes));
  CHECK_FALSE(base64Decode("Zm9", bytes));
  CHECK_FALSE(base64Decode("Zm9v!A==", bytes));
}

TEST_CASE("PNG encode/decode round-trips and names the file when damaged", "[report]") {
  sb::Image<uint8_t> grey(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) grey(x, y) = static_cast<uint8_t>(x * 50 + y);
  const auto png = encodePng(grey);
  const auto back = decodePngGray(png, "grey.png");
  REQUIRE(back.width() == 5);
  REQUIRE(back.height() == 3);
  CHECK(back.pixels() == grey.pixels());

  sb::Image<sb::Rgb8> rgb(2, 1);
  rgb(0, 0) = {255, 255, 255};
  rgb(1, 0) = {0, 0, 0};
  const auto rgbBack = decodePngGray(encodePng(rgb), "rgb.png");
  CHECK(rgbBack(0, 0) == 255);
  CHECK(rgbBack(1, 0) == 0);

  std::vector<uint8_t> truncated(png.begin(), png.begin() + static_cast<long>(png.size() / 2));
  CHECK_THROWS_WITH(decodePngGray(truncated, "model.png"), Catch::Contains("model.png"));
  CHECK_THROWS_WITH(decodePngGray({'h', 'e', 'l', 'l', 'o', '!', '!', '!', '!'}, "x.png"), Catch::Contains("not a PNG"));
}

TEST_CASE("map difference: colours and statistics per pixel class", "[report]") {
  sb::Image<uint8_t> a(4, 1), b(4, 1);
  a(0, 0) = 0, b(0, 0) = 0;      // neither
  a(1, 0) = 100, b(1, 0) = 0;    // only a
  a(2, 0) = 0, b(2, 0) = 80;     // only b
  a(3, 0) = 100, b(3, 0) = 200;  // both, far apart
  const MapDifference d = compareMaps(a, b);
  CHECK_FALSE(d.resampled);
  CHECK(d.bothPixels == 1);
  CHECK(d.meanAbsDifference == 100);
  CHECK(d.fractionDifferent == 1.0);
  CHECK(d.fractionOnlyA == 0.25);
  CHECK(d.fractionOnlyB == 0.25);
  CHECK(d.image(0, 0).r == 255);
  CHECK(d.image(1, 0).b == 178);
  CHECK(d.image(2, 0).r == 230);
  CHECK(d.image(3, 0).r == 165);  // saturated red

  sb::Image<uint8_t> same(2, 2, 120), half(1, 1, 120);
  const MapDifference r = compareMaps(same, half);
  CHECK(r.resampled);
  CHECK(r.meanAbsDifference == 0);
  CHECK(r.image(1, 1).r == 230);
  CHECK_THROWS_AS(compareMaps(same, sb::Image<uint8_t>()), sb::Error);
}

TEST_CASE("the markup check itself rejects what is not well-formed", "[report]") {
  CHECK(checkMarkup("<!DOCTYPE html>\n<html><body><p class=\"x\">a &amp; b<br/></p></body></html>").errors.empty());
  CHECK_FALSE(checkMarkup("<html><b><i></b></i></html>").errors.empty());
  CHECK_FALSE(checkMarkup("<html><p>a & b</p></html>").errors.empty());
  CHECK_FALSE(checkMarkup("<html><p x=1></p></html>").errors.empty());
  CHECK_FALSE(checkMarkup("<html><p>open</html>").errors.empty());
  CHECK_FALSE(checkMarkup("<html><p>1 < 2</p></html>").errors.empty());
  CHECK_FALSE(checkMarkup("<html></html><html></html>").errors.empty());
}

TEST_CASE("the short forms shown in report/README.md build well-formed plots", "[report]") {
  const std::vector<double> frames{0, 1, 2}, ite{0.5, 0.7, 0.6};
  LinePlot p;
  p.series.push_back({"SLAMBooster", frames, ite});
  p.events.push_back({"surface", {1}});
  BarChart b;
  b.categories = {"lr0", "kitchen"};
  b.groups = {{"DEFAULT", {149, 131}}, {"SLAMBooster", {31.9, 28}}};
  XyPlot t;
  t.series = {{"ground truth", frames, ite, "#555555", LineStyle::line, 1.5, true}, {"estimate", ite, frames}};
  for (const std::string& svg : {svgLinePlot(p), svgBarChart(b), svgXyPlot(t)}) CHECK(checkMarkup(svg).errors.empty());
}
