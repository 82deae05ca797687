#include "report/html_page.h"

#include <algorithm>

#include "report/base64.h"
#include "report/text_escape.h"

namespace sb::report {

namespace {

// No '>' in the style sheet: it keeps the <style> content trivially valid as XML text.
constexpr const char* kStyle = R"(
body { font-family: sans-serif; margin: 1.5em auto; max-width: 1100px; color: #222; padding: 0 1em; }
h1 { font-size: 1.6em; } h2 { font-size: 1.3em; margin-top: 1.6em; border-bottom: 1px solid #ddd; }
table { border-collapse: collapse; margin: 0.6em 0; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
th { background: #f3f3f3; }
figure { margin: 0.8em 0; display: inline-block; vertical-align: top; }
figcaption { font-size: 0.88em; color: #555; max-width: 820px; }
figure img { max-width: 100%; image-rendering: pixelated; border: 1px solid #ccc; }
.row { display: flex; flex-wrap: wrap; gap: 1em; align-items: flex-start; }
.row figure { margin: 0; flex: 0 1 340px; }
.row figure img { width: 100%; }
.problems { background: #fff4e5; border: 1px solid #f0b46c; padding: 0.5em 1em; }
.muted { color: #666; }
pre { background: #f7f7f7; padding: 0.6em; overflow-x: auto; font-size: 0.85em; }
)";

}  // namespace

HtmlPage::HtmlPage(const std::string& title) : title_(title) {}

void HtmlPage::heading(int level, const std::string& text, const std::string& id) {
  const std::string tag = "h" + std::to_string(std::clamp(level, 1, 4));
  body_ += "<" + tag + (id.empty() ? "" : " id=\"" + escapeXml(id) + "\"") + ">" + escapeXml(text) + "</" + tag + ">\n";
}

void HtmlPage::paragraph(const std::string& text, const std::string& cssClass) {
  body_ += "<p" + (cssClass.empty() ? std::string() : " class=\"" + escapeXml(cssClass) + "\"") + ">" +
           escapeXml(text) + "</p>\n";
}

void HtmlPage::problems(const std::vector<std::string>& list) {
  if (list.empty()) return;
  body_ += "<div class=\"problems\"><p><strong>Problems with the inputs</strong> (the report shows "
           "what could be read):</p>\n<ul>\n";
  for (const auto& p : list) body_ += "<li>" + escapeXml(p) + "</li>\n";
  body_ += "</ul></div>\n";
}

void HtmlPage::table(const Table& t, const std::string& cssClass) {
  body_ += "<table" + (cssClass.empty() ? std::string() : " class=\"" + escapeXml(cssClass) + "\"") + ">\n";
  if (!t.header.empty()) {
    body_ += "<thead><tr>";
    for (const auto& h : t.header) body_ += "<th>" + escapeXml(h) + "</th>";
    body_ += "</tr></thead>\n";
  }
  body_ += "<tbody>\n";
  for (const auto& row : t.rows) {
    body_ += "<tr>";
    for (const auto& c : row) {
      body_ += "<td";
      if (c.numeric) body_ += " class=\"num\"";
      if (!c.key.empty()) body_ += " data-key=\"" + escapeXml(c.key) + "\"";
      body_ += ">";
      body_ += c.href.empty() ? escapeXml(c.text)
                              : "<a href=\"" + escapeXml(c.href) + "\">" + escapeXml(c.text) + "</a>";
      body_ += "</td>";
    }
    body_ += "</tr>\n";
  }
  body_ += "</tbody></table>\n";
}

std::string HtmlPage::figureMarkup(const std::string& svgMarkup, const std::string& caption) {
  return "<figure>\n" + svgMarkup +
         (caption.empty() ? std::string() : "<figcaption>" + escapeXml(caption) + "</figcaption>\n") + "</figure>\n";
}

std::string HtmlPage::imageMarkup(const std::vector<uint8_t>& png, const std::string& alt, const std::string& caption) {
  return "<figure>\n<img src=\"data:image/png;base64," + base64Encode(png) + "\" alt=\"" + escapeXml(alt) + "\"/>\n" +
         (caption.empty() ? std::string() : "<figcaption>" + escapeXml(caption) + "</figcaption>\n") + "</figure>\n";
}

void HtmlPage::figure(const std::string& svgMarkup, const std::string& caption) {
  body_ += "<div>\n" + figureMarkup(svgMarkup, caption) + "</div>\n";
}

void HtmlPage::image(const std::vector<uint8_t>& png, const std::string& alt, const std::string& caption) {
  body_ += "<div>\n" + imageMarkup(png, alt, caption) + "</div>\n";
}

void HtmlPage::row(const std::vector<std::string>& items) {
  body_ += "<div class=\"row\">\n";
  for (const auto& item : items) body_ += item;
  body_ += "</div>\n";
}

void HtmlPage::link(const std::string& href, const std::string& text, const std::string& before) {
  body_ += "<p>" + escapeXml(before) + "<a href=\"" + escapeXml(href) + "\">" + escapeXml(text) + "</a></p>\n";
}

void HtmlPage::beginDetails(const std::string& summary) {
  body_ += "<details><summary>" + escapeXml(summary) + "</summary>\n";
}

void HtmlPage::endDetails() { body_ += "</details>\n"; }

void HtmlPage::details(const std::string& summary, const std::string& preformatted) {
  body_ += "<details><summary>" + escapeXml(summary) + "</summary>\n<pre>" + escapeXml(preformatted) +
           "</pre></details>\n";
}

std::string HtmlPage::str() const {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"/>\n<title>" +
         escapeXml(title_) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n<h1>" + escapeXml(title_) +
         "</h1>\n" + body_ + "</body>\n</html>\n";
}

}  // namespace sb::report
