#pragma once
// Escaping of text for HTML and SVG (both are written as XML-compatible markup), and number formatting for
// labels and tables.

#include <string>

namespace sb::report {

// Escapes &, <, >, " and ' so the text is safe inside element content and double-quoted attributes.
// Control characters other than tab/newline (not allowed in XML) become U+FFFD.
std::string escapeXml(const std::string& text);

// Shortest of %.<significant>g that reads back to the same value at that precision; "nan"/"inf" spelled out,
// negative zero printed as "0".
std::string formatNumber(double value, int significant = 6);

}  // namespace sb::report
