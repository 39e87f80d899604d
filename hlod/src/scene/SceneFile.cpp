// Scene files (docs/scene.md): one boundary where a scene's JSON is validated; past it the
// renderer and loader trust the values (ranges asserted there).
#include "hlod/scene/SceneFile.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "hlod/JsonDepth.h"

namespace hlod {

namespace {

using nlohmann::json;

std::string range(double lo, double hi) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%g..%g", lo, hi);
  return buf;
}

std::string listOf(const std::vector<std::string>& names) {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}

std::string printable(std::string key) {
  key = key.substr(0, 40);
  for (char& c : key)
    if (static_cast<unsigned char>(c) < 0x20 || c == '"') c = '?';
  return key;
}

// One JSON object read field by field; `where` names it in errors ("effects.fog.").
class Fields {
 public:
  Fields(const json& j, std::string where) : j_(j), where_(std::move(where)) {}

  Status known(const std::vector<std::string>& names, const char* what = "field") const {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      bool found = false;
      for (const auto& n : names) found = found || n == it.key();
      if (!found)
        return makeError(where_ + printable(it.key()) + ": unknown " + what +
                         " (known: " + listOf(names) + ")");
    }
    return Ok{};
  }
  bool has(const char* name) const { return j_.contains(name); }
  std::string where(const char* name) const { return where_ + name; }

  Result<double> number(const char* name, double fallback, double lo, double hi) const {
    if (!has(name)) return fallback;
    const json& v = j_.at(name);
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < lo ||
        v.get<double>() > hi)
      return makeError(where(name) + ": must be a number in " + range(lo, hi) + " (got " +
                       v.dump().substr(0, 40) + ")");
    return v.get<double>();
  }
  Result<int> integer(const char* name, int fallback, int lo, int hi) const {
    if (!has(name)) return fallback;
    const json& v = j_.at(name);
    if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
      return makeError(where(name) + ": must be an integer in " + std::to_string(lo) + ".." +
                       std::to_string(hi) + " (got " + v.dump().substr(0, 40) + ")");
    return static_cast<int>(v.get<long long>());
  }
  Result<std::string> string(const char* name) const {
    const json& v = j_.at(name);
    if (!v.is_string() || v.get<std::string>().empty() || v.get<std::string>().size() > 4096)
      return makeError(where(name) + ": must be a non-empty string");
    return v.get<std::string>();
  }
  Result<glm::dvec3> vec3(const char* name, double lo, double hi) const {
    const json& v = j_.at(name);
    const Error bad{where(name) + ": must be an array of 3 numbers in " + range(lo, hi)};
    if (!v.is_array() || v.size() != 3) return bad;
    glm::dvec3 out(0.0);
    for (int i = 0; i < 3; ++i) {
      if (!v[i].is_number() || !std::isfinite(v[i].get<double>())) return bad;
      out[i] = v[i].get<double>();
      if (out[i] < lo || out[i] > hi) return bad;
    }
    return out;
  }
  Result<glm::vec3> colour(const char* name, glm::vec3 fallback) const {
    if (!has(name)) return fallback;
    auto c = vec3(name, 0.0, 1.0);
    if (!c) return c.error();
    return glm::vec3(*c);
  }
  const json& at(const char* name) const { return j_.at(name); }

 private:
  const json& j_;
  std::string where_;
};

// An effect's value: false (off), true (on with defaults) or an object of its settings.
// Returns nullopt when off; otherwise the object to read (empty for true).
Result<std::optional<json>> effectValue(const json& v, const std::string& where) {
  if (v.is_boolean()) {
    if (!v.get<bool>()) return std::optional<json>{};
    return std::optional<json>{json::object()};
  }
  if (!v.is_object()) return makeError(where + ": must be true, false or an object");
  return std::optional<json>{v};
}

Result<SunLight> readSun(const json& j, const std::string& where) {
  Fields f(j, where + ".");
  if (auto k = f.known({"direction", "colour", "intensity"}); !k) return k.error();
  SunLight sun;
  if (f.has("direction")) {
    auto d = f.vec3("direction", -1e6, 1e6);
    if (!d) return d.error();
    if (glm::length(*d) < 1e-9) return makeError(f.where("direction") + ": must not be zero");
    sun.direction = glm::normalize(*d);
  }
  auto c = f.colour("colour", sun.colour);
  if (!c) return c.error();
  sun.colour = *c;
  auto i = f.number("intensity", sun.intensity, 0.0, 10.0);
  if (!i) return i.error();
  sun.intensity = static_cast<float>(*i);
  return sun;
}

Result<FogEffect> readFog(const json& j, const std::string& where) {
  Fields f(j, where + ".");
  if (auto k = f.known({"density"}); !k) return k.error();
  FogEffect fog;
  auto d = f.number("density", 0.0, 0.0, 1.0);
  if (!d) return d.error();
  fog.density = *d;
  return fog;
}

Result<ShadowEffect> readShadows(const json& j, const std::string& where) {
  Fields f(j, where + ".");
  if (auto k = f.known({"resolution"}); !k) return k.error();
  ShadowEffect s;
  auto r = f.integer("resolution", s.resolution, 256, 8192);
  if (!r) return r.error();
  s.resolution = *r;
  return s;
}

Result<SsaoEffect> readSsao(const json& j, const std::string& where) {
  Fields f(j, where + ".");
  if (auto k = f.known({"radius", "samples", "strength"}); !k) return k.error();
  SsaoEffect s;
  auto r = f.number("radius", s.radius, 1e-6, 1e6);
  if (!r) return r.error();
  s.radius = *r;
  auto n = f.integer("samples", s.samples, 4, 64);
  if (!n) return n.error();
  s.samples = *n;
  auto st = f.number("strength", s.strength, 0.0, 4.0);
  if (!st) return st.error();
  s.strength = static_cast<float>(*st);
  return s;
}

Result<OutlineEffect> readOutline(const json& j, const std::string& where) {
  Fields f(j, where + ".");
  if (auto k = f.known({"colour", "thickness", "threshold"}); !k) return k.error();
  OutlineEffect o;
  auto c = f.colour("colour", o.colour);
  if (!c) return c.error();
  o.colour = *c;
  auto t = f.number("thickness", o.thickness, 0.5, 8.0);
  if (!t) return t.error();
  o.thickness = static_cast<float>(*t);
  auto th = f.number("threshold", o.threshold, 1e-4, 1.0);
  if (!th) return th.error();
  o.threshold = static_cast<float>(*th);
  return o;
}

// Reads one effect by name into effects; false leaves it off.
Status readEffect(const std::string& name, const json& v, const std::string& where,
                  SceneEffects& e) {
  if (name == "textures") {
    if (!v.is_boolean()) return makeError(where + ": must be true or false");
    e.textures = v.get<bool>();
    return Ok{};
  }
  if (name == "shading") {
    const char* const names[] = {"unlit", "lambert", "blinn-phong"};
    const Shading values[] = {Shading::Unlit, Shading::Lambert, Shading::BlinnPhong};
    for (int i = 0; i < 3; ++i)
      if (v.is_string() && v.get<std::string>() == names[i]) {
        e.shading = values[i];
        return Ok{};
      }
    return makeError(where + ": must be one of unlit, lambert, blinn-phong");
  }
  auto value = effectValue(v, where);
  if (!value) return value.error();
  if (!*value) return Ok{};  // declared off
  const json& j = **value;
  if (name == "sun") {
    auto s = readSun(j, where);
    if (!s) return s.error();
    e.sun = *s;
  } else if (name == "fog") {
    auto f = readFog(j, where);
    if (!f) return f.error();
    e.fog = *f;
  } else if (name == "shadows") {
    auto s = readShadows(j, where);
    if (!s) return s.error();
    e.shadows = *s;
  } else if (name == "ssao") {
    auto s = readSsao(j, where);
    if (!s) return s.error();
    e.ssao = *s;
  } else {
    assert(name == "outline");
    auto o = readOutline(j, where);
    if (!o) return o.error();
    e.outline = *o;
  }
  return Ok{};
}

Result<Background> readBackground(const json& j) {
  Background b;
  if (!j.is_object()) return makeError("background: must be an object");
  Fields f(j, "background.");
  if (auto k = f.known({"colour", "sky"}); !k) return k.error();
  if (f.has("colour") == f.has("sky"))
    return makeError("background: give either \"colour\" (flat) or \"sky\" (a gradient)");
  if (f.has("colour")) {
    auto c = f.colour("colour", b.colour);
    if (!c) return c.error();
    b.colour = *c;
    return b;
  }
  const json& sky = f.at("sky");
  if (!sky.is_object()) return makeError("background.sky: must be an object");
  Fields s(sky, "background.sky.");
  if (auto k = s.known({"horizon", "zenith", "ground"}); !k) return k.error();
  b.sky = true;
  b.colour = {0.78f, 0.85f, 0.92f};
  auto h = s.colour("horizon", b.colour);
  if (!h) return h.error();
  b.colour = *h;
  auto z = s.colour("zenith", b.zenith);
  if (!z) return z.error();
  b.zenith = *z;
  auto g = s.colour("ground", b.ground);
  if (!g) return g.error();
  b.ground = *g;
  return b;
}

Result<SceneEffects> readEffects(const json& j, const std::string& where) {
  if (!j.is_object()) return makeError(where + ": must be an object");
  SceneEffects e;
  Fields f(j, where + ".");
  if (auto k = f.known(knownEffects(), "effect"); !k) return k.error();
  for (auto it = j.begin(); it != j.end(); ++it)
    if (auto st = readEffect(it.key(), it.value(), where + "." + it.key(), e); !st)
      return st.error();
  // A shadow map is cast by the sun, and only a lit surface shows it.
  if (e.shadows && !e.sun) return makeError(where + ".shadows: needs a \"sun\"");
  if (e.shadows && !e.lit())
    return makeError(where + ".shadows: needs lit shading (lambert or blinn-phong)");
  return e;
}

Result<json> parseJson(const std::string& text) {
  // Scene files are small and written by people: a deep nesting is a mistake, not a scene.
  if (jsonDepth(text, 16) > 16) return makeError("nested deeper than 16 levels");
  json j = json::parse(text, nullptr, false);
  if (j.is_discarded()) return makeError("not valid JSON");
  return j;
}

}  // namespace

SceneEffects defaultEffects() {
  SceneEffects e;
  e.textures = true;
  e.shading = Shading::Lambert;
  e.sun = SunLight{};
  return e;
}

std::vector<std::string> declaredEffects(const SceneEffects& e) {
  std::vector<std::string> out;
  if (e.shading == Shading::Lambert) out.push_back("lambert");
  if (e.shading == Shading::BlinnPhong) out.push_back("blinn-phong");
  if (e.textures) out.push_back("textures");
  if (e.sun) out.push_back("sun");
  if (e.background.sky) out.push_back("sky");
  if (e.fog) out.push_back("fog");
  if (e.shadows) out.push_back("shadows");
  if (e.ssao) out.push_back("ssao");
  if (e.outline) out.push_back("outline");
  return out;
}

const std::vector<std::string>& knownEffects() {
  static const std::vector<std::string> names = {"textures", "shading", "sun",    "fog",
                                                 "shadows",  "ssao",    "outline"};
  return names;
}

Result<SceneFile> parseScene(const std::string& text) {
  auto parsed = parseJson(text);
  if (!parsed) return parsed.error();
  const json& j = *parsed;
  if (!j.is_object()) return makeError("a scene must be a JSON object");
  Fields f(j, "");
  if (auto k = f.known({"store", "camera", "background", "effects"}); !k) return k.error();
  SceneFile scene;
  if (f.has("store")) {
    auto s = f.string("store");
    if (!s) return s.error();
    scene.store = *s;
  }
  if (f.has("camera")) {
    const json& c = f.at("camera");
    if (!c.is_object()) return makeError("camera: must be an object");
    Fields cf(c, "camera.");
    if (auto k = cf.known({"position", "target", "up", "fov"}); !k) return k.error();
    if (!cf.has("position") || !cf.has("target"))
      return makeError("camera: needs \"position\" and \"target\"");
    SceneCamera cam;
    auto p = cf.vec3("position", -1e12, 1e12);
    if (!p) return p.error();
    auto t = cf.vec3("target", -1e12, 1e12);
    if (!t) return t.error();
    cam.position = *p;
    cam.target = *t;
    if (glm::length(cam.target - cam.position) < 1e-9)
      return makeError("camera: position and target must differ");
    if (cf.has("up")) {
      auto u = cf.vec3("up", -1e6, 1e6);
      if (!u) return u.error();
      if (glm::length(*u) < 1e-9) return makeError("camera.up: must not be zero");
      cam.up = glm::normalize(*u);
    }
    auto fov = cf.number("fov", cam.fov, 1.0, 170.0);
    if (!fov) return fov.error();
    cam.fov = *fov;
    scene.camera = cam;
  }
  if (f.has("background")) {
    auto b = readBackground(f.at("background"));
    if (!b) return b.error();
    scene.effects.background = *b;
  }
  if (f.has("effects")) {
    const Background b = scene.effects.background;
    auto e = readEffects(f.at("effects"), "effects");
    if (!e) return e.error();
    scene.effects = *e;
    scene.effects.background = b;
  }
  return scene;
}

Result<SceneFile> readSceneFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path.string() + ": cannot read the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().size() > (1u << 20)) return makeError(path.string() + ": larger than 1 MiB");
  auto scene = parseScene(text.str());
  if (!scene) return makeError(path.string() + ": " + scene.message());
  return scene;
}

double fogDensityFor(const FogEffect& fog, double farDistance) {
  if (fog.density > 0.0) return fog.density;
  return farDistance > 0.0 ? 1.0 / farDistance : 0.0;
}

double fogCullDistance(double density) {
  // exp(-density d) < 1/510 <=> d > ln(510) / density.
  return density > 0.0 ? std::log(510.0) / density : INFINITY;
}

}  // namespace hlod
