#pragma once
// Every setting a user gives hlodr, on the command line or over HTTP, in one table: its names
// (the command's option, the API's field), its range, its default and what it means. The
// commands (service/src/cmd) and the API (server/ApiTypes.cpp, server/routes) read values
// through it, `--help` prints its lines (a usage text names a setting as {id}), and the
// settings tables of docs/api.md are generated from it (`hlodr help settings --markdown`; a
// test keeps them equal). A new setting is one row in Settings.cpp, used where it is read.
#include <string>
#include <string_view>
#include <vector>

namespace service {

struct Setting {
  enum class Kind {
    Number,      // a finite number in [lo, hi]
    Integer,     // a whole number in [lo, hi]
    Choice,      // one of choices
    Flag,        // on or off (a bare --name; true/false over HTTP)
    Size,        // WxH, each side an integer in [lo, hi]
    NumberList,  // 1..16 numbers, each in [lo, hi] ("8,16,33"; a JSON array)
    ChoiceList,  // 1..choices.size() of choices
    Text,        // free text (an address, a folder)
  };
  std::string id;   // unique: how usage texts and the code name it ("budgetMs", "serve.port")
  std::string cli;  // the option without "--" ("budget-ms"); "" when the CLI has none
  std::string api;  // the JSON field ("budgetMs"); "" when the API has none
  Kind kind = Kind::Number;
  double lo = 0.0, hi = 0.0;
  std::string fallback;              // the default as text ("33", "lakhia", "1280x720"); "" none
  std::vector<std::string> choices;  // Choice, ChoiceList
  std::string metavar;               // the value in --help ("MS")
  std::string meaning;               // what it does, one sentence
  std::string where;                 // where it is taken: "render --path, POST /api/jobs"

  double fallbackNumber() const;  // the default of a Number or Integer (0 when it has none)
  std::string range() const;      // "0.5..10000", "lakhia, sse, fs or full", "on or off"
};

namespace settings {

// The table, in the order --help and the docs list it.
const std::vector<Setting>& all();
// The row with this id; the program is wrong (it asserts) when there is none.
const Setting& get(std::string_view id);
const Setting* find(std::string_view id);  // nullptr when there is none

}  // namespace settings

// The items of a comma-separated list ("8,16,33"): a setting's default, or what a user gave.
std::vector<std::string> splitList(const std::string& text);

// "  --budget-ms MS          the frame time budget: 0.5..10000 ms (default 33)", wrapped at 100
// columns.
std::string helpLine(const Setting& s);
// A usage text with each "{id}" line replaced by its setting's help line.
std::string expandUsage(const char* usage);
// The settings as a Markdown table (`hlodr help settings --markdown [WHICH]`): "api" (those the
// HTTP API takes), "serve" (the server's options) or "all"; or all of them as text.
std::string settingsMarkdown(std::string_view which);
std::string settingsText();

}  // namespace service
