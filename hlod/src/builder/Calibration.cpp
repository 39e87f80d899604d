#include "hlod/builder/Calibration.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace hlod {

Result<std::filesystem::path> calibrationPath() {
  if (const char* p = std::getenv("HLODR_CALIBRATION"); p && *p) return std::filesystem::path(p);
  if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x)
    return std::filesystem::path(x) / "hlodr" / "calibration.json";
  if (const char* h = std::getenv("HOME"); h && *h)
    return std::filesystem::path(h) / ".config" / "hlodr" / "calibration.json";
  return makeError(
      "no calibration location: neither HLODR_CALIBRATION, XDG_CONFIG_HOME nor HOME is set");
}

Result<std::optional<double>> readCalibratedCTex() {
  auto path = calibrationPath();
  if (!path) return std::optional<double>();
  std::error_code ec;
  if (!std::filesystem::exists(*path, ec)) return std::optional<double>();
  std::ifstream in(*path);
  if (!in) return makeError("calibration file " + path->string() + " cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  const auto json = nlohmann::json::parse(text.str(), nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded() || !json.is_object())
    return makeError("calibration file " + path->string() + " is not a JSON object");
  const auto it = json.find("cTex");
  if (it == json.end() || !it->is_number())
    return makeError("calibration file " + path->string() + " has no number \"cTex\"");
  const double c = it->get<double>();
  if (!std::isfinite(c) || c < 0.0 || c > 1.0)
    return makeError("calibration file " + path->string() + ": cTex is outside [0, 1]");
  return std::optional<double>(c);
}

Status writeCalibration(double cTex) {
  if (!std::isfinite(cTex) || cTex < 0.0 || cTex > 1.0) return makeError("cTex outside [0, 1]");
  auto path = calibrationPath();
  if (!path) return path.error();
  std::error_code ec;
  if (path->has_parent_path()) std::filesystem::create_directories(path->parent_path(), ec);
  if (ec) return makeError("cannot create " + path->parent_path().string() + ": " + ec.message());
  std::ofstream out(*path, std::ios::trunc);
  out << nlohmann::json{{"cTex", cTex}}.dump(2) << "\n";
  out.close();
  if (!out) return makeError("cannot write " + path->string());
  return Ok{};
}

}  // namespace hlod
