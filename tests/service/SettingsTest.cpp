// The table of settings is the one source of every setting's range, default and meaning: the
// tables of docs/api.md are generated from it, the usage texts name only settings it has, its
// defaults are in their ranges, and the selector's ssePixels constant has the API's range.
#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "hlod/runtime/Selector.h"
#include "service/Cli.h"
#include "service/Settings.h"

namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(Settings, TheTablesOfDocsApiAreTheGeneratedOnes) {
  const std::string doc = readFile(std::string(HLODR_TEST_DATA) + "/../../docs/api.md");
  ASSERT_FALSE(doc.empty());
  for (const char* which : {"api", "serve"}) {
    const std::string open = std::string("<!-- settings:") + which + " ";
    const auto start = doc.find(open);
    ASSERT_NE(start, std::string::npos) << "docs/api.md has no block " << open;
    const auto body = doc.find("-->\n", start) + 4;
    const auto end = doc.find("<!-- /settings -->", body);
    ASSERT_NE(end, std::string::npos);
    EXPECT_EQ(doc.substr(body, end - body), service::settingsMarkdown(which))
        << "regenerate the block with `hlodr help settings --markdown " << which << "`";
  }
}

TEST(Settings, EveryUsageTextNamesOnlySettingsOfTheTable) {
  for (const auto& c : service::commands()) {
    std::istringstream lines(c.usage);
    for (std::string line; std::getline(lines, line);) {
      if (line.size() > 2 && line.front() == '{' && line.back() == '}') {
        EXPECT_NE(service::settings::find(line.substr(1, line.size() - 2)), nullptr)
            << c.name << ": " << line;
      }
    }
    const std::string help = service::expandUsage(c.usage);
    EXPECT_EQ(help.find("\n{"), std::string::npos) << c.name;
  }
  // A help line says the range and the default.
  const std::string line = service::helpLine(service::settings::get("budgetMs"));
  EXPECT_NE(line.find("--budget-ms MS"), std::string::npos) << line;
  EXPECT_NE(line.find("0.5..10000"), std::string::npos) << line;
  EXPECT_NE(line.find("(default 33)"), std::string::npos) << line;
}

TEST(Settings, EveryDefaultIsInsideItsRangeAndIdsAreUnique) {
  using K = service::Setting::Kind;
  std::set<std::string> ids;
  for (const service::Setting& s : service::settings::all()) {
    EXPECT_TRUE(ids.insert(s.id).second) << s.id;
    EXPECT_FALSE(s.cli.empty() && s.api.empty()) << s.id;
    EXPECT_FALSE(s.meaning.empty()) << s.id;
    if (s.fallback.empty()) continue;
    if (s.kind == K::Number || s.kind == K::Integer) {
      EXPECT_GE(s.fallbackNumber(), s.lo) << s.id;
      EXPECT_LE(s.fallbackNumber(), s.hi) << s.id;
    }
    if (s.kind == K::Choice) {
      EXPECT_NE(std::find(s.choices.begin(), s.choices.end(), s.fallback), s.choices.end()) << s.id;
    }
    if (s.kind == K::NumberList)
      for (const std::string& item : service::splitList(s.fallback)) {
        EXPECT_GE(std::stod(item), s.lo) << s.id;
        EXPECT_LE(std::stod(item), s.hi) << s.id;
      }
  }
}

// The API's ssePx and the selector constant ssePixels (--params) are one threshold: one range.
TEST(Settings, TheSseThresholdHasOneRangeForTheApiAndTheSelectorConstant) {
  const service::Setting& sse = service::settings::get("ssePx");
  hlod::SelectorParams p;
  EXPECT_TRUE(hlod::setSelectorParam(p, "ssePixels", sse.lo).ok());
  EXPECT_TRUE(hlod::setSelectorParam(p, "ssePixels", sse.hi).ok());
  EXPECT_FALSE(hlod::setSelectorParam(p, "ssePixels", sse.lo * 0.999).ok());
  EXPECT_FALSE(hlod::setSelectorParam(p, "ssePixels", sse.hi * 1.001).ok());
  const service::Setting& list = service::settings::get("study.ssePx");
  EXPECT_EQ(list.lo, sse.lo);
  EXPECT_EQ(list.hi, sse.hi);
  EXPECT_EQ(service::settings::get("study.budgets").lo, service::settings::get("budgetMs").lo);
  EXPECT_EQ(service::settings::get("study.budgets").hi, service::settings::get("budgetMs").hi);
}
