#pragma once
// A self-contained HTML page assembled in order: headings, text, tables, inline SVG figures and PNG images
// embedded as data: URIs, so the file views offline with nothing beside it. The markup is well-formed XML
// (every element closed, void elements self-closed, attributes quoted, text escaped).

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sb::report {

struct TableCell {
  TableCell(std::string cellText = "", std::string dataKey = "", bool isNumeric = false,
            std::string link = "")
      : text(std::move(cellText)), key(std::move(dataKey)), numeric(isNumeric), href(std::move(link)) {}
  std::string text;
  std::string key;   // when set: the cell carries data-key="key" (tests and scripts find values by it)
  bool numeric;      // right-aligned
  std::string href;  // when set: the text links there (e.g. a relative path to another report)
};

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<TableCell>> rows;
};

class HtmlPage {
 public:
  explicit HtmlPage(const std::string& title);

  void heading(int level, const std::string& text, const std::string& id = "");  // level 1-4
  void paragraph(const std::string& text, const std::string& cssClass = "");
  // A list of problems with the inputs, shown prominently; nothing when `problems` is empty.
  void problems(const std::vector<std::string>& problems);
  void table(const Table& table, const std::string& cssClass = "");
  // An <svg> element from the plot functions, with an optional caption.
  void figure(const std::string& svgMarkup, const std::string& caption = "");
  // A PNG image embedded as a data: URI, with alt text and an optional caption.
  void image(const std::vector<uint8_t>& png, const std::string& alt, const std::string& caption = "");
  // Several figures side by side (each: inner markup from figureMarkup/imageMarkup), wrapping on narrow screens.
  void row(const std::vector<std::string>& items);
  void link(const std::string& href, const std::string& text, const std::string& before = "");
  // A collapsible block (closed) around what is added until endDetails().
  void beginDetails(const std::string& summary);
  void endDetails();
  // Collapsible block with preformatted text (e.g. the full config JSON).
  void details(const std::string& summary, const std::string& preformatted);

  static std::string figureMarkup(const std::string& svgMarkup, const std::string& caption);
  static std::string imageMarkup(const std::vector<uint8_t>& png, const std::string& alt, const std::string& caption);

  std::string str() const;

 private:
  std::string title_;
  std::string body_;
};

}  // namespace sb::report
