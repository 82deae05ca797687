// config/controller.json and the controller tables of config/README.md against the code: every registered
// controller's settings struct (its toJson() at the defaults), key by key, so that a key added to the code
// and not to the file or the documentation (or the other way round) fails here.

#include <catch2/catch.hpp>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "controller/registry.h"

namespace {

// Values config/controller.json sets away from the code's default, and why.
const std::map<std::string, std::string> kFileSets = {
    {"fixed.preset", "the shipped file runs `fixed` at the default preset, not the pipeline config's knobs"},
    {"budget.target_frame_ms", "budget has no default target; the file sets 33.3 ms"},
};

// One section's defaults per section name (every controller of a section shares its settings struct).
std::map<std::string, nlohmann::json> codeDefaults() {
  std::map<std::string, nlohmann::json> sections;
  for (const sb::ControllerType& t : sb::controllerTypes())
    if (!t.section.empty()) sections[t.section] = t.defaults();
  return sections;
}

std::string readText(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in.good());
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

// "a, [1,2], b" -> {"a", "[1,2]", "b"}: commas inside brackets do not split.
std::vector<std::string> splitTop(const std::string& text) {
  std::vector<std::string> parts;
  std::string part;
  int depth = 0;
  for (char c : text) {
    if (c == '[') ++depth;
    if (c == ']') --depth;
    if (c == ',' && depth == 0) {
      parts.push_back(trim(part));
      part.clear();
    } else {
      part += c;
    }
  }
  parts.push_back(trim(part));
  return parts;
}

// A documented default: "(empty)" is "", "(none)" is an absent key (null here), `x` is the string x, anything
// else is JSON with an optional remark in parentheses after it ("0 (off)").
nlohmann::json documentedValue(const std::string& cell) {
  if (cell == "(empty)") return "";
  if (cell == "(none)") return nullptr;
  if (cell.size() > 2 && cell.front() == '`' && cell.back() == '`') return cell.substr(1, cell.size() - 2);
  const std::string value = trim(cell.substr(0, cell.find(" (")));
  return nlohmann::json::parse(value);
}

struct DocumentedKey {
  std::string cell;      // the default cell as written
  nlohmann::json value;  // parsed, or null for "as `other`"
  std::string sameAs;    // "as `other`": the other section's documented value
};

// config/README.md: each "`SECTION` section keys" paragraph's table, key -> documented default.
std::map<std::string, std::map<std::string, DocumentedKey>> documentedTables(const std::string& text) {
  std::map<std::string, std::map<std::string, DocumentedKey>> tables;
  const std::regex heading("^`([a-z_]+)` section keys"), backticked("`([^`]+)`"), sameAs("^as `([a-z_]+)`$");
  std::istringstream in(text);
  std::string line, section;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, heading)) {
      section = m[1];
      continue;
    }
    if (section.empty()) continue;
    if (line.empty() && !tables[section].empty()) {
      section.clear();
      continue;
    }
    if (line.rfind("| `", 0) != 0) continue;  // the header and separator rows
    std::vector<std::string> cells;
    std::string cell;
    for (size_t i = 1; i < line.size(); ++i) {
      if (line[i] == '|') {
        cells.push_back(trim(cell));
        cell.clear();
      } else {
        cell += line[i];
      }
    }
    INFO("config/README.md, `" << section << "` table: " << line);
    REQUIRE(cells.size() >= 3);
    std::vector<std::string> keys;
    for (auto it = std::sregex_iterator(cells[0].begin(), cells[0].end(), backticked);
         it != std::sregex_iterator(); ++it)
      keys.push_back((*it)[1]);
    std::smatch same;
    if (std::regex_match(cells[2], same, sameAs)) {
      for (const std::string& k : keys) tables[section][k] = {cells[2], nullptr, same[1]};
      continue;
    }
    const std::vector<std::string> values = splitTop(cells[2]);
    REQUIRE(values.size() == keys.size());
    for (size_t i = 0; i < keys.size(); ++i)
      tables[section][keys[i]] = {values[i], documentedValue(values[i]), ""};
  }
  return tables;
}

}  // namespace

TEST_CASE("config/controller.json parses and selects adaptive", "[controller][config]") {
  const auto file = nlohmann::json::parse(readText(SB_CONTROLLER_CONFIG)).at("controller");
  const sb::ControllerContext context;
  const auto settings = sb::parseControllerSettings(file, context, SB_CONTROLLER_CONFIG);
  CHECK(settings.name == "adaptive");
}

TEST_CASE("config/controller.json holds every key of every section at the code's default",
          "[controller][config]") {
  const auto file = nlohmann::json::parse(readText(SB_CONTROLLER_CONFIG)).at("controller");
  const sb::ControllerContext context;
  for (const auto& [section, defaults] : codeDefaults()) {
    INFO("section '" << section << "'");
    if (!file.contains(section)) {
      // Only a section that cannot run at its defaults (a required key: tc's table, offline's result) is
      // absent.
      sb::ControllerSettings s;
      s.sections[section] = nlohmann::json::object();
      for (const sb::ControllerType& t : sb::controllerTypes())
        if (t.section == section) CHECK_THROWS_AS(sb::createController(t.name, s, context), sb::Error);
      continue;
    }
    const nlohmann::json& inFile = file.at(section);
    for (const auto& [key, value] : defaults.items()) {
      INFO("key '" << key << "'");
      REQUIRE(inFile.contains(key));  // a key of the code missing from the file
      if (kFileSets.count(section + "." + key))
        CHECK(inFile.at(key) != value);  // the exception is still one
      else
        CHECK(inFile.at(key) == value);
    }
    for (const auto& [key, value] : inFile.items()) {
      INFO("key '" << key << "'");
      CHECK(defaults.contains(key));  // a key in the file that the code does not read
    }
  }
  for (const auto& [key, why] : kFileSets) {
    INFO(key << ": " << why);
    const std::string section = key.substr(0, key.find('.'));
    CHECK(file.contains(section));
  }
}

TEST_CASE("config/README.md documents every controller key at the code's default", "[controller][config]") {
  const auto tables = documentedTables(readText(SB_CONFIG_README));
  const auto defaults = codeDefaults();
  for (const auto& [section, code] : defaults) {
    INFO("config/README.md: the `" << section << "` section keys table");
    REQUIRE(tables.count(section));
    const auto& documented = tables.at(section);
    for (const auto& [key, value] : code.items()) {
      INFO("key '" << key << "' = " << value.dump());
      REQUIRE(documented.count(key));  // a key of the code missing from the table
      const DocumentedKey& d = documented.at(key);
      nlohmann::json expected = d.value;
      if (!d.sameAs.empty()) {
        REQUIRE(tables.count(d.sameAs));
        REQUIRE(tables.at(d.sameAs).count(key));
        expected = tables.at(d.sameAs).at(key).value;
      }
      INFO("documented: " << d.cell);
      CHECK(expected == value);
    }
    for (const auto& [key, d] : documented) {
      INFO("documented key '" << key << "'");
      // A key the code does not emit: only one documented as absent by default ("(none)").
      if (!code.contains(key)) CHECK(d.value.is_null());
      if (!code.contains(key)) CHECK(d.sameAs.empty());
    }
  }
  for (const auto& [section, documented] : tables) {
    INFO("config/README.md documents a `" << section << "` section");
    CHECK(defaults.count(section));
  }
}
