#pragma once
// Command-line arguments of one subcommand: positionals, `--name value`, `--name=value`, and
// boolean flags. Unknown options are reported, not ignored.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "hlod/Result.h"
#include "service/Settings.h"

namespace service {

class Args {
 public:
  // flags: option names that take no value (e.g. "quiet", "plots"); every other --name takes one.
  static hlod::Result<Args> parse(const std::vector<std::string>& argv,
                                  const std::set<std::string>& flags,
                                  const std::set<std::string>& options);

  const std::vector<std::string>& positionals() const { return positionals_; }
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::optional<std::string> get(const std::string& name) const;
  std::string get(const std::string& name, const std::string& fallback) const;
  // Numeric options: an Error for a value that is not a number or is outside [lo, hi].
  hlod::Result<double> number(const std::string& name, double fallback, double lo, double hi) const;
  hlod::Result<long long> integer(const std::string& name, long long fallback, long long lo,
                                  long long hi) const;
  // A switch `--name on|off`: fallback when absent, an Error naming it for any other value.
  hlod::Result<bool> onOff(const std::string& name, bool fallback) const;
  // A frame size WxH (fallback when absent, and the message's example), each side in [lo, hi].
  struct Size {
    int width = 0;
    int height = 0;
  };
  hlod::Result<Size> size(const std::string& name, const std::string& fallback, int lo,
                          int hi) const;

  // A setting of the table (service/Settings.h) by its option: its default when absent; an
  // Error that names the option and its range otherwise.
  hlod::Result<double> number(const Setting& s) const;
  hlod::Result<long long> integer(const Setting& s) const;
  hlod::Result<std::string> choice(const Setting& s) const;
  hlod::Result<Size> size(const Setting& s) const;
  hlod::Result<std::vector<double>> numbers(const Setting& s) const;
  hlod::Result<std::vector<std::string>> choices(const Setting& s) const;

 private:
  std::vector<std::string> positionals_;
  std::map<std::string, std::string> values_;
};

}  // namespace service
