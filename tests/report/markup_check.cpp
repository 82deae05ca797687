#include "tests/report/markup_check.h"

#include <cctype>
#include <cstdlib>

namespace sb::test {

namespace {

class Parser {
 public:
  explicit Parser(const std::string& doc) : doc_(doc) {}

  MarkupCheck run() {
    skipDoctype();
    while (pos_ < doc_.size() && result_.errors.size() < 20) {
      if (doc_[pos_] == '<') {
        tag();
      } else {
        const size_t end = doc_.find('<', pos_);
        text(doc_.substr(pos_, end == std::string::npos ? std::string::npos : end - pos_));
        pos_ = end == std::string::npos ? doc_.size() : end;
      }
    }
    for (auto it = open_.rbegin(); it != open_.rend(); ++it) error("element <" + it->name + "> is never closed");
    if (closedRoots_ != 1) error("expected exactly one root element, found " + std::to_string(closedRoots_));
    return std::move(result_);
  }

 private:
  void error(const std::string& what) {
    size_t line = 1;
    for (size_t i = 0; i < pos_ && i < doc_.size(); ++i) line += doc_[i] == '\n';
    result_.errors.push_back("line " + std::to_string(line) + ": " + what);
  }

  void skipDoctype() {
    if (doc_.compare(0, 9, "<!DOCTYPE") == 0 || doc_.compare(0, 9, "<!doctype") == 0) pos_ = doc_.find('>') + 1;
  }

  // Decodes entities; reports a bare '&' or an unknown entity.
  std::string decode(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
      if (s[i] != '&') {
        out += s[i];
        continue;
      }
      const size_t semi = s.find(';', i);
      const std::string name = semi == std::string::npos ? "" : s.substr(i + 1, semi - i - 1);
      if (name == "amp") out += '&';
      else if (name == "lt") out += '<';
      else if (name == "gt") out += '>';
      else if (name == "quot") out += '"';
      else if (name == "apos") out += '\'';
      else if (name.size() > 1 && name[0] == '#') {
        const bool hex = name[1] == 'x';
        char* end = nullptr;
        const long code = std::strtol(name.c_str() + (hex ? 2 : 1), &end, hex ? 16 : 10);
        if (*end != '\0' || code <= 0 || code > 0x10FFFF) error("bad character reference '&" + name + ";'");
        else if (code < 0x80) out += static_cast<char>(code);
        else out += "?";  // tests only compare ASCII
      } else {
        error("'&' not starting a known entity: '" + s.substr(i, 12) + "'");
        continue;
      }
      i = semi;
    }
    return out;
  }

  void text(const std::string& raw) {
    const std::string t = decode(raw);
    if (!open_.empty()) open_.back().text += t;
    else if (t.find_first_not_of(" \t\r\n") != std::string::npos) error("text outside the root element");
  }

  void tag() {
    if (doc_.compare(pos_, 4, "<!--") == 0) {
      const size_t end = doc_.find("-->", pos_);
      if (end == std::string::npos) return error("comment never closed"), void(pos_ = doc_.size());
      pos_ = end + 3;
      return;
    }
    ++pos_;
    const bool closing = pos_ < doc_.size() && doc_[pos_] == '/';
    if (closing) ++pos_;
    const std::string name = nameToken();
    if (name.empty()) return error("'<' not starting a tag (escape it as &lt;)"), void(pos_ = doc_.find('>', pos_));
    if (closing) {
      skipSpace();
      if (!expect('>')) return;
      close(name);
      return;
    }
    MarkupElement e;
    e.name = name;
    while (true) {
      skipSpace();
      if (pos_ >= doc_.size()) return error("tag <" + name + "> never ends");
      if (doc_.compare(pos_, 2, "/>") == 0) {
        pos_ += 2;
        open_.push_back(std::move(e));
        close(name);
        return;
      }
      if (doc_[pos_] == '>') {
        ++pos_;
        break;
      }
      const std::string attr = nameToken();
      if (attr.empty()) return error("bad attribute syntax in <" + name + ">"), void(pos_ = doc_.find('>', pos_));
      if (!expect('=') || !expect('"')) return void(pos_ = doc_.find('>', pos_));
      const size_t end = doc_.find('"', pos_);
      if (end == std::string::npos) return error("attribute value never closed");
      const std::string value = doc_.substr(pos_, end - pos_);
      if (value.find('<') != std::string::npos) error("'<' inside the value of attribute '" + attr + "'");
      if (e.attributes.count(attr)) error("attribute '" + attr + "' repeated in <" + name + ">");
      e.attributes[attr] = decode(value);
      pos_ = end + 1;
    }
    open_.push_back(std::move(e));
    if (name == "style" || name == "script") {
      const std::string endTag = "</" + name;
      const size_t end = doc_.find(endTag, pos_);
      if (end == std::string::npos) return error("<" + name + "> never closed");
      open_.back().text = doc_.substr(pos_, end - pos_);
      pos_ = end;
    }
  }

  void close(const std::string& name) {
    if (open_.empty() || open_.back().name != name) {
      error("</" + name + "> does not close the open element" + (open_.empty() ? "" : " <" + open_.back().name + ">"));
      return;
    }
    MarkupElement e = std::move(open_.back());
    open_.pop_back();
    if (!open_.empty()) open_.back().text += e.text;
    else ++closedRoots_;
    result_.elements.push_back(std::move(e));
  }

  std::string nameToken() {
    std::string n;
    while (pos_ < doc_.size() && (std::isalnum(static_cast<unsigned char>(doc_[pos_])) || doc_[pos_] == '-' ||
                                  doc_[pos_] == ':' || doc_[pos_] == '_'))
      n += static_cast<char>(std::tolower(static_cast<unsigned char>(doc_[pos_++])));
    return n;
  }

  void skipSpace() {
    while (pos_ < doc_.size() && std::isspace(static_cast<unsigned char>(doc_[pos_]))) ++pos_;
  }

  bool expect(char c) {
    if (pos_ < doc_.size() && doc_[pos_] == c) {
      ++pos_;
      return true;
    }
    error(std::string("expected '") + c + "'");
    return false;
  }

  const std::string& doc_;
  size_t pos_ = 0;
  std::vector<MarkupElement> open_;
  int closedRoots_ = 0;
  MarkupCheck result_;
};

}  // namespace

std::vector<const MarkupElement*> MarkupCheck::find(const std::string& name) const {
  std::vector<const MarkupElement*> out;
  for (const auto& e : elements)
    if (e.name == name) out.push_back(&e);
  return out;
}

MarkupCheck checkMarkup(const std::string& document) { return Parser(document).run(); }

}  // namespace sb::test
