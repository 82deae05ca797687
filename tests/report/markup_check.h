#pragma once
// A strict well-formedness check of the report's markup (XML rules applied to the HTML page: every element
// closed in order, attributes double-quoted, '&' only as an entity, no '<' in text), which also collects the
// elements so tests can query attributes and text.

#include <map>
#include <string>
#include <vector>

namespace sb::test {

struct MarkupElement {
  std::string name;                               // lower-case tag name
  std::map<std::string, std::string> attributes;  // values entity-decoded
  std::string text;                               // all text inside, entity-decoded
};

struct MarkupCheck {
  std::vector<std::string> errors;      // "line 12: ..."; empty when well-formed
  std::vector<MarkupElement> elements;  // in closing order
  std::vector<const MarkupElement*> find(const std::string& name) const;
};

// `<!DOCTYPE ...>` and comments are allowed; <style> and <script> content is raw text.
MarkupCheck checkMarkup(const std::string& document);

}  // namespace sb::test
