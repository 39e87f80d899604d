#pragma once
// The JSON body of a request, read field by field with errors that name the field and its
// range: the one place where the API's input is validated. Rejects bodies nested deeper than
// kMaxDepth before parsing, and fields the endpoint does not know (a typo is an error, not a
// silently ignored setting).
#include <initializer_list>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hlod/Result.h"
#include "hlod/runtime/Camera.h"
#include "service/Settings.h"

namespace service::server {

class JsonInput {
 public:
  static constexpr int kMaxDepth = 16;
  // body must be a JSON object (an empty body reads as {}); known: the fields it may hold.
  static hlod::Result<JsonInput> parse(const std::string& body, std::set<std::string> known);
  // A sub-object (e.g. "camera"), with its own known fields; the prefix names it in errors.
  static hlod::Result<JsonInput> of(const nlohmann::json& object, const std::string& prefix,
                                    std::set<std::string> known);

  bool has(const char* name) const { return json_.contains(name); }
  const nlohmann::json& json() const { return json_; }
  hlod::Result<double> number(const char* name, double fallback, double lo, double hi) const;
  hlod::Result<long long> integer(const char* name, long long fallback, long long lo,
                                  long long hi) const;
  hlod::Result<bool> boolean(const char* name, bool fallback) const;
  hlod::Result<std::string> choice(const char* name, const std::string& fallback,
                                   std::initializer_list<const char*> allowed) const;
  hlod::Result<std::string> string(const char* name, std::size_t maxLength) const;  // required
  hlod::Result<glm::dvec3> vec3(const char* name) const;                            // required

  // A setting of the table (service/Settings.h) by its field (Setting::api after its last '.'):
  // its default when absent, an Error naming the field and its range otherwise. hi lowers the
  // table's upper bound (width and height: --max-size).
  hlod::Result<double> number(const Setting& s) const;
  hlod::Result<long long> integer(const Setting& s, long long hi = 0) const;
  hlod::Result<std::string> choice(const Setting& s) const;
  hlod::Result<bool> boolean(const Setting& s) const;
  hlod::Result<std::vector<double>> numbers(const Setting& s) const;
  hlod::Result<std::vector<std::string>> choices(const Setting& s) const;

 private:
  std::string where(const char* name) const { return prefix_ + name; }
  nlohmann::json json_;
  std::string prefix_;
};

// {"position", "target", "up", "fov"} into a camera; absent fields come from `fallback`.
hlod::Result<hlod::Camera> cameraFrom(const nlohmann::json& camera, const hlod::Camera& fallback);
nlohmann::json cameraJson(const hlod::Camera& camera);

}  // namespace service::server
