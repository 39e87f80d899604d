// A camera path's JSON file: its keyframes read (every field checked, then fromKeyframes) and
// written (hlod/runtime/CameraPath.h gives the format).
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hlod/runtime/CameraPath.h"

namespace hlod {

namespace {

using nlohmann::json;

Result<glm::dvec3> readVec3(const json& j, const char* key, std::size_t index) {
  const std::string where = "keyframe " + std::to_string(index) + ": \"" + key + "\"";
  if (!j.contains(key)) return makeError(where + " is missing");
  const json& v = j.at(key);
  if (!v.is_array() || v.size() != 3) return makeError(where + " must be an array of 3 numbers");
  glm::dvec3 out;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number()) return makeError(where + " must be an array of 3 numbers");
    out[i] = v[i].get<double>();
  }
  return out;
}

json toJson(const glm::dvec3& v) {
  return json::array({v.x, v.y, v.z});
}

}  // namespace

Result<CameraPath> CameraPath::parse(std::string_view text) {
  json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return makeError("camera path: malformed JSON");
  const json* list = &j;
  if (j.is_object()) {
    if (!j.contains("keyframes")) return makeError("camera path: no \"keyframes\" array");
    list = &j.at("keyframes");
  }
  if (!list->is_array()) return makeError("camera path: \"keyframes\" must be an array");
  std::vector<CameraKeyframe> keys;
  for (std::size_t i = 0; i < list->size(); ++i) {
    const json& k = (*list)[i];
    const std::string where = "keyframe " + std::to_string(i);
    if (!k.is_object()) return makeError(where + " must be an object");
    CameraKeyframe kf;
    if (!k.contains("time") || !k.at("time").is_number()) {
      return makeError(where + ": \"time\" must be a number");
    }
    kf.time = k.at("time").get<double>();
    auto pos = readVec3(k, "position", i);
    if (!pos) return pos.error();
    auto tgt = readVec3(k, "target", i);
    if (!tgt) return tgt.error();
    kf.position = *pos;
    kf.target = *tgt;
    if (k.contains("up")) {
      auto up = readVec3(k, "up", i);
      if (!up) return up.error();
      kf.up = *up;
    }
    if (k.contains("fov")) {
      if (!k.at("fov").is_number()) return makeError(where + ": \"fov\" must be a number");
      kf.fovY = k.at("fov").get<double>();
    }
    keys.push_back(kf);
  }
  return fromKeyframes(std::move(keys));
}

Result<CameraPath> CameraPath::read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError("cannot open camera path '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  auto p = parse(ss.str());
  if (!p) return makeError(path + ": " + p.message());
  return p;
}

std::string CameraPath::toJson() const {
  json keys = json::array();
  for (const CameraKeyframe& k : keys_) {
    keys.push_back({{"time", k.time},
                    {"position", hlod::toJson(k.position)},
                    {"target", hlod::toJson(k.target)},
                    {"up", hlod::toJson(k.up)},
                    {"fov", k.fovY}});
  }
  return json{{"keyframes", keys}}.dump(2);
}

Status CameraPath::write(const std::string& path) const {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return makeError("cannot write camera path '" + path + "'");
  out << toJson() << '\n';
  if (!out) return makeError("error writing camera path '" + path + "'");
  return Ok{};
}

}  // namespace hlod
