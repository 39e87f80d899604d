#include "service/Args.h"

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace service {

namespace {

std::string joinedChoices(const std::vector<std::string>& choices) {
  std::string out;
  for (const auto& c : choices) out += (out.empty() ? "" : ", ") + c;
  return out;
}

}  // namespace

hlod::Result<Args> Args::parse(const std::vector<std::string>& argv,
                               const std::set<std::string>& flags,
                               const std::set<std::string>& options) {
  Args args;
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (a.size() > 2 && a.rfind("--", 0) == 0) {
      std::string name = a.substr(2), value;
      const auto eq = name.find('=');
      const bool inlineValue = eq != std::string::npos;
      if (inlineValue) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
      }
      if (flags.count(name)) {
        if (inlineValue) return hlod::makeError("option --" + name + " takes no value");
        // Moved in rather than assigned from "1": g++ 12 at -O3 reports a false -Wrestrict
        // overlap in std::string's assignment from a literal (GCC bug 105329).
        args.values_.insert_or_assign(name, std::string("1"));
      } else if (options.count(name)) {
        if (!inlineValue) {
          if (i + 1 >= argv.size()) return hlod::makeError("option --" + name + " needs a value");
          value = argv[++i];
        }
        args.values_[name] = value;
      } else {
        return hlod::makeError("unknown option --" + name);
      }
    } else if (a.size() == 2 && a[0] == '-' && a[1] != '-') {
      // Short aliases: -o for --output.
      const std::string name = a == "-o" ? "output" : "";
      if (name.empty() || !options.count(name)) return hlod::makeError("unknown option " + a);
      if (i + 1 >= argv.size()) return hlod::makeError("option " + a + " needs a value");
      args.values_[name] = argv[++i];
    } else {
      args.positionals_.push_back(a);
    }
  }
  return args;
}

std::optional<std::string> Args::get(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

std::string Args::get(const std::string& name, const std::string& fallback) const {
  return get(name).value_or(fallback);
}

hlod::Result<double> Args::number(const std::string& name, double fallback, double lo,
                                  double hi) const {
  const auto v = get(name);
  if (!v) return fallback;
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(v->c_str(), &end);
  if (v->empty() || *end != '\0' || errno != 0 || !std::isfinite(x))
    return hlod::makeError("--" + name + ": '" + *v + "' is not a number");
  if (x < lo || x > hi) {
    char range[64];
    std::snprintf(range, sizeof range, "[%g, %g]", lo, hi);
    return hlod::makeError("--" + name + ": " + *v + " is outside " + range);
  }
  return x;
}

hlod::Result<bool> Args::onOff(const std::string& name, bool fallback) const {
  const auto v = get(name);
  if (!v) return fallback;
  if (*v != "on" && *v != "off")
    return hlod::makeError("--" + name + ": '" + *v + "' must be on or off");
  return *v == "on";
}

hlod::Result<long long> Args::integer(const std::string& name, long long fallback, long long lo,
                                      long long hi) const {
  const auto v = get(name);
  if (!v) return fallback;
  errno = 0;
  char* end = nullptr;
  const long long x = std::strtoll(v->c_str(), &end, 10);
  if (v->empty() || *end != '\0' || errno != 0)
    return hlod::makeError("--" + name + ": '" + *v + "' is not an integer");
  if (x < lo || x > hi)
    return hlod::makeError("--" + name + ": " + *v + " is outside [" + std::to_string(lo) + ", " +
                           std::to_string(hi) + "]");
  return x;
}

hlod::Result<Args::Size> Args::size(const std::string& name, const std::string& fallback, int lo,
                                    int hi) const {
  const std::string v = get(name, fallback);
  Size out;
  char extra = 0;
  // Digits first and no sign or blank anywhere: sscanf alone takes " +1x2".
  const bool plain = v.find_first_not_of("0123456789x") == std::string::npos;
  if (!plain || std::sscanf(v.c_str(), "%dx%d%c", &out.width, &out.height, &extra) != 2 ||
      out.width < lo || out.height < lo || out.width > hi || out.height > hi) {
    return hlod::makeError("--" + name + " must look like " + fallback + " (" + std::to_string(lo) +
                           ".." + std::to_string(hi) + " each side), not '" + v + "'");
  }
  return out;
}

hlod::Result<double> Args::number(const Setting& s) const {
  assert(s.kind == Setting::Kind::Number);
  return number(s.cli, s.fallbackNumber(), s.lo, s.hi);
}

hlod::Result<long long> Args::integer(const Setting& s) const {
  assert(s.kind == Setting::Kind::Integer);
  return integer(s.cli, static_cast<long long>(s.fallbackNumber()), static_cast<long long>(s.lo),
                 static_cast<long long>(s.hi));
}

hlod::Result<std::string> Args::choice(const Setting& s) const {
  assert(s.kind == Setting::Kind::Choice);
  const std::string v = get(s.cli, s.fallback);
  for (const std::string& c : s.choices)
    if (v == c) return v;
  return hlod::makeError("--" + s.cli + " must be " + s.range() + " (not '" + v + "')");
}

hlod::Result<Args::Size> Args::size(const Setting& s) const {
  assert(s.kind == Setting::Kind::Size);
  return size(s.cli, s.fallback, int(s.lo), int(s.hi));
}

hlod::Result<std::vector<double>> Args::numbers(const Setting& s) const {
  assert(s.kind == Setting::Kind::NumberList);
  const std::string list = get(s.cli, s.fallback);
  std::vector<double> out;
  for (const std::string& item : splitList(list)) {
    errno = 0;
    char* stop = nullptr;
    const double v = std::strtod(item.c_str(), &stop);
    if (item.empty() || *stop != '\0' || errno != 0 || !std::isfinite(v) || v < s.lo || v > s.hi ||
        out.size() == 16)
      return hlod::makeError("--" + s.cli + ": '" + list + "' is not " + s.range());
    out.push_back(v);
  }
  return out;
}

hlod::Result<std::vector<std::string>> Args::choices(const Setting& s) const {
  assert(s.kind == Setting::Kind::ChoiceList);
  std::vector<std::string> out;
  for (const std::string& item : splitList(get(s.cli, s.fallback))) {
    if (std::find(s.choices.begin(), s.choices.end(), item) == s.choices.end())
      return hlod::makeError("--" + s.cli + ": '" + item + "' is not one of " +
                             joinedChoices(s.choices));
    out.push_back(item);
  }
  return out;
}

}  // namespace service
