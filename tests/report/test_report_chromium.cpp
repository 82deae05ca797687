// The report opened in headless Chromium (Debian's `chromium`): it loads without console errors, every
// image decodes and every plot has a size. A control page with a script error and a broken image proves that
// the check sees such faults. Without chromium the test is skipped (exit 77) with the reason, except under
// CI, where chromium must be installed (scripts/install_deps.sh).

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "tests/report/report_fixture.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace fs = std::filesystem;
using sb::test::readText;
using sb::test::runCommand;

namespace {

// After load, writes what it found into <body data-render-check="...">, which --dump-dom prints.
const char* kProbe = R"(<script>
window.addEventListener('load', function () {
  var bad = [];
  var images = document.images;
  for (var i = 0; i < images.length; ++i)
    if (!images[i].complete || images[i].naturalWidth === 0) bad.push('img' + i);
  var svgs = document.querySelectorAll('svg');
  for (var k = 0; k < svgs.length; ++k) {
    var box = svgs[k].getBoundingClientRect();
    if (box.width === 0 || box.height === 0) bad.push('svg' + k);
  }
  document.body.setAttribute('data-render-check',
      'images=' + images.length + ' svgs=' + svgs.length + ' bad=' + bad.join(','));
});
</script>
)";

struct Rendered {
  std::string dom, log;
};

// A copy of `page` with the probe before </body>, opened in headless chromium.
Rendered render(const std::string& page, const std::string& scratch) {
  std::string html = readText(page);
  const size_t body = html.rfind("</body>");
  REQUIRE(body != std::string::npos);
  html.insert(body, kProbe);
  const std::string probed = scratch + "/probed.html";
  sb::test::writeText(probed, html);
  const std::string log = scratch + "/chromium.log";
  // In a subshell: runCommand adds its own 2>&1, which must not take chromium's log away from the file.
  const auto r = runCommand("(timeout 120 chromium --headless --disable-gpu --no-sandbox --user-data-dir=" + scratch +
                            "/profile --enable-logging=stderr --v=0 --virtual-time-budget=10000 --dump-dom file://" +
                            fs::absolute(probed).string() + " 2>" + log + ")");
  INFO(readText(log));
  REQUIRE(r.exitCode == 0);
  return {r.output, readText(log)};
}

// Any console message counts: the report has no scripts, so nothing should ever write to the console
// (Chromium logs them as "INFO:CONSOLE:<line>] ..." or "ERROR:CONSOLE(...)").
bool hasConsoleError(const std::string& log) {
  return log.find("Uncaught") != std::string::npos || log.find(":CONSOLE") != std::string::npos;
}

void requireChromium() {
  if (runCommand("command -v chromium").exitCode == 0) return;
  const bool ci = std::getenv("CI") != nullptr;
  std::cerr << (ci ? "FAILED" : "SKIPPED")
            << ": chromium is not installed (scripts/install_deps.sh installs it)"
            << (ci ? "; CI is set, so a missing chromium is a failure" : "") << "\n";
  std::exit(ci ? 1 : 77);
}

}  // namespace

TEST_CASE("the run report and the comparison render in headless chromium without errors", "[report][chromium]") {
  requireChromium();
  const auto& runs = sb::test::reportRuns("report_chromium");
  const std::string tool = SB_SLAMBOOSTER_BIN;
  REQUIRE(runCommand(tool + " report " + runs.runA).exitCode == 0);
  REQUIRE(runCommand(tool + " report " + runs.runA + " --compare " + runs.runB).exitCode == 0);

  const auto single = render(runs.runA + "/report.html", sb::test::scratchDir("report_chromium_single"));
  INFO(single.log);
  CHECK_FALSE(hasConsoleError(single.log));
  CHECK_THAT(single.dom, Catch::Contains("data-render-check=\"images=1 svgs="));
  CHECK_THAT(single.dom, Catch::Contains(" bad=\""));
  CHECK_THAT(single.dom, Catch::Contains("SLAMBooster run: csr4"));

  const auto compare = render(runs.runA + "/compare-csr8.html", sb::test::scratchDir("report_chromium_compare"));
  INFO(compare.log);
  CHECK_FALSE(hasConsoleError(compare.log));
  CHECK_THAT(compare.dom, Catch::Contains("data-render-check=\"images=4 svgs="));
  CHECK_THAT(compare.dom, Catch::Contains(" bad=\""));
}

TEST_CASE("the chromium check catches a script error and a broken image", "[report][chromium]") {
  requireChromium();
  const std::string scratch = sb::test::scratchDir("report_chromium_control");
  sb::test::writeText(scratch + "/control.html",
                      "<!DOCTYPE html><html><head><title>control</title></head><body>"
                      "<img src=\"data:image/png;base64,iVBORw0KGgoAAAAN\" alt=\"broken\"/>"
                      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"></svg>"
                      "<script>notDefinedAnywhere();</script></body></html>");
  const auto control = render(scratch + "/control.html", scratch);
  CHECK(hasConsoleError(control.log));
  CHECK_THAT(control.dom, Catch::Contains("data-render-check=\"images=1 svgs=1 bad=img0\""));
}
