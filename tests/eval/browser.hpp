#pragma once
// Headless Chromium for the tests of hazmap's static pages (eval/report.html,
// view.html): the page opened from file:// as a user would, its DOM after the scripts
// ran, a screenshot, and what the page wrote to the console.
// Needs Debian's `chromium` (tools/install_deps.sh installs it). Without it a test fails
// with a clear message; HAZMAP_SKIP_BROWSER=1 skips the browser tests.

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace hazmap::testing {

inline bool browser_tests_skipped() {
  const char* skip = std::getenv("HAZMAP_SKIP_BROWSER");
  return skip && std::string(skip) == "1";
}

inline bool chromium_found() { return std::system("command -v chromium > /dev/null 2>&1") == 0; }

constexpr const char* kNoChromium =
    "chromium not found: install Debian's chromium (tools/install_deps.sh does), or set "
    "HAZMAP_SKIP_BROWSER=1 to skip this test";

/// Headless Chromium with its own profile folder and nothing that reaches the network.
inline std::string chromium_command(const std::filesystem::path& profile) {
  return "timeout 180 chromium --headless --no-sandbox --disable-gpu "
         "--disable-background-networking --disable-component-update --disable-sync "
         "--no-first-run --hide-scrollbars --user-data-dir=" +
         profile.string();
}

/// What one Chromium run left: its exit code, standard output and standard error, which
/// holds the console (--enable-logging=stderr).
struct BrowserRun {
  int exit_code = -1;
  std::string output;
  std::string log;
};

/// Opens `url` with `flags` (e.g. "--dump-dom"), console messages logged. Virtual time
/// lets the page's asynchronous work (promises, timers) finish before the DOM is dumped
/// or the screenshot taken, without waiting for real seconds.
inline BrowserRun run_chromium(const std::filesystem::path& work, const std::string& name,
                               const std::string& flags, const std::string& url) {
  const std::filesystem::path out = work / (name + ".out"), err = work / (name + ".err");
  const int status = std::system((chromium_command(work / ("profile_" + name)) +
                                  " --virtual-time-budget=10000 --enable-logging=stderr --v=0 " +
                                  flags + " '" + url + "' > " + out.string() + " 2> " + err.string())
                                     .c_str());
  BrowserRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.output = read_text(out);
  r.log = read_text(err);
  return r;
}

/// The console messages in a Chromium log (lines "...:CONSOLE:<line>] "message", source:").
inline std::vector<std::string> console_messages(const std::string& log) {
  std::vector<std::string> lines;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.find(":CONSOLE") != std::string::npos) lines.push_back(line);
  return lines;
}

}  // namespace hazmap::testing
