#include "server/JsonInput.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>

#include "hlod/JsonDepth.h"

namespace service::server {

namespace {

std::string range(double lo, double hi) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%g..%g", lo, hi);
  return buf;
}

hlod::Status checkKnown(const nlohmann::json& j, const std::string& prefix,
                        const std::set<std::string>& known) {
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (known.count(it.key())) continue;
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    std::string key = it.key().substr(0, 40);
    for (char& c : key)
      if (static_cast<unsigned char>(c) < 0x20 || c == '"') c = '?';
    return hlod::makeError(prefix + key + ": unknown field (known: " + list + ")");
  }
  return hlod::Ok{};
}

}  // namespace

hlod::Result<JsonInput> JsonInput::parse(const std::string& body, std::set<std::string> known) {
  // A body of 20,000 brackets is refused before a parser recurses into it.
  if (hlod::jsonDepth(body, std::size_t(kMaxDepth)) > std::size_t(kMaxDepth))
    return hlod::makeError("the body is nested deeper than " + std::to_string(kMaxDepth) +
                           " levels");
  JsonInput in;
  if (body.find_first_not_of(" \t\r\n") == std::string::npos) {
    in.json_ = nlohmann::json::object();
  } else {
    in.json_ = nlohmann::json::parse(body, nullptr, false);
    if (in.json_.is_discarded()) return hlod::makeError("the body is not valid JSON");
  }
  if (!in.json_.is_object()) return hlod::makeError("the body must be a JSON object");
  if (auto k = checkKnown(in.json_, "", known); !k) return k.error();
  return in;
}

hlod::Result<JsonInput> JsonInput::of(const nlohmann::json& object, const std::string& prefix,
                                      std::set<std::string> known) {
  if (!object.is_object()) return hlod::makeError(prefix + ": must be an object");
  JsonInput in;
  in.json_ = object;
  in.prefix_ = prefix + ".";
  if (auto k = checkKnown(object, in.prefix_, known); !k) return k.error();
  return in;
}

hlod::Result<double> JsonInput::number(const char* name, double fallback, double lo,
                                       double hi) const {
  if (!json_.contains(name)) return fallback;
  const auto& v = json_[name];
  if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < lo ||
      v.get<double>() > hi)
    return hlod::makeError(where(name) + ": must be a number in " + range(lo, hi) + " (got " +
                           v.dump().substr(0, 40) + ")");
  return v.get<double>();
}

hlod::Result<long long> JsonInput::integer(const char* name, long long fallback, long long lo,
                                           long long hi) const {
  if (!json_.contains(name)) return fallback;
  const auto& v = json_[name];
  const bool whole =
      v.is_number_integer() ||
      (v.is_number_float() && std::isfinite(v.get<double>()) &&
       std::floor(v.get<double>()) == v.get<double>() && std::abs(v.get<double>()) < 9e15);
  if (!whole || v.get<double>() < double(lo) || v.get<double>() > double(hi))
    return hlod::makeError(where(name) + ": must be an integer in " + std::to_string(lo) + ".." +
                           std::to_string(hi) + " (got " + v.dump().substr(0, 40) + ")");
  return static_cast<long long>(v.get<double>());
}

hlod::Result<bool> JsonInput::boolean(const char* name, bool fallback) const {
  if (!json_.contains(name)) return fallback;
  if (!json_[name].is_boolean()) return hlod::makeError(where(name) + ": must be true or false");
  return json_[name].get<bool>();
}

hlod::Result<std::string> JsonInput::choice(const char* name, const std::string& fallback,
                                            std::initializer_list<const char*> allowed) const {
  std::string list;
  for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
  if (!json_.contains(name)) return fallback;
  const auto& v = json_[name];
  if (v.is_string())
    for (const char* a : allowed)
      if (v.get<std::string>() == a) return std::string(a);
  return hlod::makeError(where(name) + ": must be one of " + list);
}

hlod::Result<std::string> JsonInput::string(const char* name, std::size_t maxLength) const {
  if (!json_.contains(name)) return hlod::makeError(where(name) + ": is required");
  const auto& v = json_[name];
  if (!v.is_string() || v.get<std::string>().empty() || v.get<std::string>().size() > maxLength)
    return hlod::makeError(where(name) + ": must be a string of 1.." + std::to_string(maxLength) +
                           " characters");
  return v.get<std::string>();
}

hlod::Result<glm::dvec3> JsonInput::vec3(const char* name) const {
  const auto& v = json_[name];
  if (!v.is_array() || v.size() != 3)
    return hlod::makeError(where(name) + ": must be an array of 3 finite numbers");
  glm::dvec3 out;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>()) ||
        std::abs(v[i].get<double>()) > 1e12)
      return hlod::makeError(where(name) + ": must be an array of 3 finite numbers");
    out[i] = v[i].get<double>();
  }
  return out;
}

namespace {

std::string fieldOf(const Setting& s) {
  return s.api.substr(s.api.rfind('.') + 1);
}

}  // namespace

hlod::Result<double> JsonInput::number(const Setting& s) const {
  assert(s.kind == Setting::Kind::Number);
  return number(fieldOf(s).c_str(), s.fallbackNumber(), s.lo, s.hi);
}

hlod::Result<long long> JsonInput::integer(const Setting& s, long long hi) const {
  assert(s.kind == Setting::Kind::Integer);
  const auto top = static_cast<long long>(s.hi);
  return integer(fieldOf(s).c_str(), static_cast<long long>(s.fallbackNumber()),
                 static_cast<long long>(s.lo), hi > 0 ? std::min(hi, top) : top);
}

hlod::Result<std::string> JsonInput::choice(const Setting& s) const {
  assert(s.kind == Setting::Kind::Choice);
  const std::string name = fieldOf(s);
  if (!json_.contains(name)) return s.fallback;
  const auto& v = json_[name];
  if (v.is_string())
    for (const std::string& c : s.choices)
      if (v.get<std::string>() == c) return c;
  return hlod::makeError(where(name.c_str()) + ": must be " + s.range());
}

hlod::Result<bool> JsonInput::boolean(const Setting& s) const {
  assert(s.kind == Setting::Kind::Flag);
  return boolean(fieldOf(s).c_str(), s.fallback == "on");
}

hlod::Result<std::vector<double>> JsonInput::numbers(const Setting& s) const {
  assert(s.kind == Setting::Kind::NumberList);
  const std::string name = fieldOf(s);
  std::vector<double> out;
  if (!json_.contains(name)) {
    for (const std::string& item : splitList(s.fallback))
      out.push_back(std::strtod(item.c_str(), nullptr));
    return out;
  }
  const auto& v = json_[name];
  const std::string err = where(name.c_str()) + ": must be " + s.range();
  if (!v.is_array() || v.empty() || v.size() > 16) return hlod::makeError(err);
  for (const auto& x : v) {
    if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < s.lo ||
        x.get<double>() > s.hi)
      return hlod::makeError(err);
    out.push_back(x.get<double>());
  }
  return out;
}

hlod::Result<std::vector<std::string>> JsonInput::choices(const Setting& s) const {
  assert(s.kind == Setting::Kind::ChoiceList);
  const std::string name = fieldOf(s);
  std::vector<std::string> out;
  if (!json_.contains(name)) return splitList(s.fallback);
  const auto& v = json_[name];
  const std::string err = where(name.c_str()) + ": must be " + s.range();
  if (!v.is_array() || v.empty() || v.size() > s.choices.size()) return hlod::makeError(err);
  for (const auto& x : v) {
    if (!x.is_string() ||
        std::find(s.choices.begin(), s.choices.end(), x.get<std::string>()) == s.choices.end())
      return hlod::makeError(err);
    out.push_back(x.get<std::string>());
  }
  return out;
}

hlod::Result<hlod::Camera> cameraFrom(const nlohmann::json& camera, const hlod::Camera& fallback) {
  auto in = JsonInput::of(camera, "camera", {"position", "target", "up", "fov"});
  if (!in) return in.error();
  hlod::Camera c = fallback;
  if (in->has("position")) {
    auto p = in->vec3("position");
    if (!p) return p.error();
    c.position = *p;
  }
  if (in->has("target")) {
    auto t = in->vec3("target");
    if (!t) return t.error();
    c.target = *t;
  }
  if (in->has("up")) {
    auto u = in->vec3("up");
    if (!u) return u.error();
    if (glm::length(*u) < 1e-9) return hlod::makeError("camera.up: must not be zero");
    c.up = glm::normalize(*u);
  }
  const Setting& fovRange = settings::get("fov");
  auto fov = in->number("fov", c.fovY, fovRange.lo, fovRange.hi);
  if (!fov) return fov.error();
  c.fovY = *fov;
  const glm::dvec3 d = c.target - c.position;
  if (glm::length(d) < 1e-9) return hlod::makeError("camera: position and target must differ");
  // Up parallel to the view: the look-at is undefined; pick another up rather than a NaN frame.
  if (glm::length(glm::cross(glm::normalize(d), c.up)) < 1e-6)
    c.up = std::abs(d.z) > std::abs(d.y) ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
  return c;
}

nlohmann::json cameraJson(const hlod::Camera& c) {
  return {{"position", {c.position.x, c.position.y, c.position.z}},
          {"target", {c.target.x, c.target.y, c.target.z}},
          {"up", {c.up.x, c.up.y, c.up.z}},
          {"fov", c.fovY}};
}

}  // namespace service::server
