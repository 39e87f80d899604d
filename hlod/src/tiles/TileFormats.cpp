// 3D Tiles tile formats: b3dm and cmpt headers, feature and batch tables (hlod/tiles/TileFormats.h;
// CesiumGS/3d-tiles specification/TileFormats/Batched3DModel, Composite, FeatureTable, BatchTable,
// schema/TileFormats/b3dm.featureTable.schema.json).
#include "hlod/tiles/TileFormats.h"

#include <cmath>
#include <cstring>

#include <nlohmann/json.hpp>

#include "hlod/JsonDepth.h"

namespace hlod::tiles {

namespace {

// The JSON nesting a tile's tables may have (the glTF reader's bound).
constexpr std::size_t kMaxTableDepth = 128;
// Legacy b3dm headers: a length field that reads as 0x22000000 (a '"', the start of JSON) or
// more is not a length (CesiumJS Batched3DModel3DTileContent, cesium-native B3dmToGltfConverter).
constexpr std::uint32_t kLegacyMark = 570425344u;

std::uint32_t u32(std::string_view b, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;  // little-endian files on little-endian hosts (as the rest of hlodr's readers)
}

bool startsWith(std::string_view b, const char* magic) {
  return b.size() >= 4 && std::memcmp(b.data(), magic, 4) == 0;
}

std::string_view trimJson(std::string_view s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\0' || s.back() == '\n'))
    s.remove_suffix(1);
  return s;
}

Result<nlohmann::json> parseTable(std::string_view text, const char* what) {
  text = trimJson(text);
  if (text.empty()) return nlohmann::json::object();
  if (jsonDepth(text, kMaxTableDepth) > kMaxTableDepth)
    return makeError(std::string(what) + " nested too deep");
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object())
    return makeError(std::string(what) + " is not a JSON object");
  return j;
}

std::size_t componentBytes(const std::string& type) {
  if (type == "BYTE" || type == "UNSIGNED_BYTE") return 1;
  if (type == "SHORT" || type == "UNSIGNED_SHORT") return 2;
  if (type == "INT" || type == "UNSIGNED_INT" || type == "FLOAT") return 4;
  if (type == "DOUBLE") return 8;
  return 0;
}

std::size_t typeComponents(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  return 0;
}

// A feature table global property: a number, an array of `n` numbers, or {byteOffset} into the
// binary body holding n values of `component` type.
Result<std::vector<double>> globalProperty(const nlohmann::json& value, std::size_t n,
                                           std::string_view body, const char* component,
                                           const char* name) {
  std::vector<double> out;
  if (value.is_number() && n == 1) return std::vector<double>{value.get<double>()};
  if (value.is_array()) {
    if (value.size() != n) return makeError(std::string(name) + " has the wrong number of values");
    for (const auto& v : value) {
      if (!v.is_number()) return makeError(std::string(name) + " holds a value that is no number");
      out.push_back(v.get<double>());
    }
    return out;
  }
  if (value.is_object() && value.contains("byteOffset") &&
      value["byteOffset"].is_number_unsigned()) {
    const std::string type = value.value("componentType", component);
    const std::size_t size = componentBytes(type);
    const std::uint64_t offset = value["byteOffset"].get<std::uint64_t>();
    if (size == 0) return makeError(std::string(name) + " has an unknown componentType");
    if (offset > body.size() || n * size > body.size() - offset)
      return makeError(std::string(name) + " lies outside the feature table's binary body");
    for (std::size_t i = 0; i < n; ++i) {
      const char* p = body.data() + offset + i * size;
      double v = 0.0;
      if (type == "FLOAT") {
        float f;
        std::memcpy(&f, p, 4);
        v = f;
      } else if (type == "DOUBLE") {
        std::memcpy(&v, p, 8);
      } else if (type == "UNSIGNED_INT") {
        std::uint32_t u;
        std::memcpy(&u, p, 4);
        v = u;
      } else if (type == "INT") {
        std::int32_t u;
        std::memcpy(&u, p, 4);
        v = u;
      } else if (type == "UNSIGNED_SHORT") {
        std::uint16_t u;
        std::memcpy(&u, p, 2);
        v = u;
      } else if (type == "SHORT") {
        std::int16_t u;
        std::memcpy(&u, p, 2);
        v = u;
      } else {
        v = type == "BYTE" ? double(std::int8_t(*p)) : double(std::uint8_t(*p));
      }
      out.push_back(v);
    }
    return out;
  }
  return makeError(std::string(name) + " is neither numbers nor a reference to the binary body");
}

}  // namespace

TileFormat detectTileFormat(std::string_view bytes) {
  if (startsWith(bytes, "glTF")) return TileFormat::Glb;
  if (startsWith(bytes, "b3dm")) return TileFormat::B3dm;
  if (startsWith(bytes, "cmpt")) return TileFormat::Cmpt;
  if (startsWith(bytes, "i3dm")) return TileFormat::I3dm;
  if (startsWith(bytes, "pnts")) return TileFormat::Pnts;
  std::size_t i = 0;
  // A UTF-8 byte-order mark and white space may precede JSON.
  if (bytes.size() >= 3 && std::memcmp(bytes.data(), "\xEF\xBB\xBF", 3) == 0) i = 3;
  while (i < bytes.size() &&
         (bytes[i] == ' ' || bytes[i] == '\n' || bytes[i] == '\r' || bytes[i] == '\t'))
    ++i;
  if (i >= bytes.size() || bytes[i] != '{') return TileFormat::Unknown;
  const std::string_view text = bytes.substr(i);
  if (jsonDepth(text, kMaxTableDepth) > kMaxTableDepth) return TileFormat::Unknown;
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("asset")) return TileFormat::Unknown;
  return j.contains("root") ? TileFormat::Tileset : TileFormat::GltfJson;
}

const char* tileFormatName(TileFormat format) {
  switch (format) {
    case TileFormat::Glb:
      return "glb";
    case TileFormat::GltfJson:
      return "glTF JSON";
    case TileFormat::Tileset:
      return "external tileset";
    case TileFormat::B3dm:
      return "b3dm";
    case TileFormat::Cmpt:
      return "cmpt";
    case TileFormat::I3dm:
      return "i3dm";
    case TileFormat::Pnts:
      return "pnts";
    case TileFormat::Unknown:
      break;
  }
  return "unknown";
}

Result<B3dmContent> parseB3dm(std::string_view b) {
  if (!startsWith(b, "b3dm")) return makeError("not a b3dm (magic)");
  if (b.size() < 28) return makeError("b3dm header truncated");
  if (u32(b, 4) != 1)
    return makeError("b3dm version " + std::to_string(u32(b, 4)) + " (only 1 is defined)");
  const std::uint32_t byteLength = u32(b, 8);
  if (byteLength > b.size())
    return makeError("b3dm truncated: its header says " + std::to_string(byteLength) +
                     " bytes, the file has " + std::to_string(b.size()));
  if (byteLength < 28) return makeError("b3dm byteLength smaller than its header");
  b = b.substr(0, byteLength);
  std::uint64_t ftJson = u32(b, 12), ftBin = u32(b, 16), btJson = u32(b, 20), btBin = u32(b, 24);
  std::size_t header = 28;
  std::optional<std::uint32_t> legacyBatchLength;
  if (btJson >= kLegacyMark) {
    // Legacy 1: [batchLength] [batchTableByteLength], a 20-byte header.
    header = 20;
    legacyBatchLength = std::uint32_t(ftJson);
    btJson = ftBin;
    btBin = ftJson = ftBin = 0;
  } else if (btBin >= kLegacyMark) {
    // Legacy 2: [batchTableJSONByteLength] [batchTableBinaryByteLength] [batchLength], 24 bytes.
    header = 24;
    legacyBatchLength = std::uint32_t(btJson);
    btJson = ftJson;
    btBin = ftBin;
    ftJson = ftBin = 0;
  }
  if (ftJson + ftBin + btJson + btBin > b.size() - header)
    return makeError("b3dm tables run past its end");
  std::size_t at = header;
  const std::string_view ftText = b.substr(at, ftJson);
  const std::string_view ftBody = b.substr(at + ftJson, ftBin);
  at += ftJson + ftBin;
  const std::string_view btText = b.substr(at, btJson);
  const std::string_view btBody = b.substr(at + btJson, btBin);
  at += btJson + btBin;

  B3dmContent out;
  out.glb = b.substr(at);
  auto ft = parseTable(ftText, "b3dm feature table");
  if (!ft) return ft.error();
  if (legacyBatchLength) {
    out.batchLength = *legacyBatchLength;
  } else {
    if (!ft->contains("BATCH_LENGTH"))
      return makeError("b3dm feature table has no BATCH_LENGTH (required)");
    auto n = globalProperty((*ft)["BATCH_LENGTH"], 1, ftBody, "UNSIGNED_INT", "BATCH_LENGTH");
    if (!n) return n.error();
    const double v = n->front();
    if (!(v >= 0.0 && v <= 4294967295.0) || v != double(std::uint64_t(v)))
      return makeError("b3dm BATCH_LENGTH is not a count");
    out.batchLength = std::uint32_t(v);
  }
  if (ft->contains("RTC_CENTER")) {
    auto c = globalProperty((*ft)["RTC_CENTER"], 3, ftBody, "FLOAT", "RTC_CENTER");
    if (!c) return c.error();
    const glm::dvec3 centre((*c)[0], (*c)[1], (*c)[2]);
    if (!std::isfinite(centre.x) || !std::isfinite(centre.y) || !std::isfinite(centre.z))
      return makeError("b3dm RTC_CENTER is not finite");
    out.rtcCenter = centre;
  }
  auto bt = parseTable(btText, "b3dm batch table");
  if (!bt) return bt.error();
  // Binary properties must lie inside the batch table's body (the values are not kept).
  for (const auto& [name, value] : bt->items()) {
    if (name == "extensions" || name == "extras") continue;
    ++out.batchProperties;
    if (!value.is_object() || !value.contains("byteOffset")) continue;
    if (!value["byteOffset"].is_number_unsigned() || !value.contains("componentType") ||
        !value["componentType"].is_string() || !value.contains("type") ||
        !value["type"].is_string())
      return makeError("b3dm batch table property '" + name + "' is a malformed binary reference");
    const std::size_t size = componentBytes(value["componentType"].get<std::string>()) *
                             typeComponents(value["type"].get<std::string>());
    const std::uint64_t offset = value["byteOffset"].get<std::uint64_t>();
    if (size == 0 || offset > btBody.size() ||
        std::uint64_t(out.batchLength) * size > btBody.size() - offset)
      return makeError("b3dm batch table property '" + name +
                       "' lies outside the batch table's binary body");
  }
  if (!startsWith(out.glb, "glTF")) return makeError("b3dm holds no binary glTF after its tables");
  return out;
}

Result<std::vector<std::string_view>> parseCmpt(std::string_view b) {
  if (!startsWith(b, "cmpt")) return makeError("not a cmpt (magic)");
  if (b.size() < 16) return makeError("cmpt header truncated");
  if (u32(b, 4) != 1)
    return makeError("cmpt version " + std::to_string(u32(b, 4)) + " (only 1 is defined)");
  const std::uint32_t byteLength = u32(b, 8);
  if (byteLength > b.size() || byteLength < 16) return makeError("cmpt truncated");
  b = b.substr(0, byteLength);
  const std::uint32_t count = u32(b, 12);
  std::vector<std::string_view> tiles;
  std::size_t at = 16;
  for (std::uint32_t i = 0; i < count; ++i) {
    if (b.size() - at < 12) return makeError("cmpt inner tile " + std::to_string(i) + " truncated");
    const std::uint32_t length = u32(b, at + 8);
    if (length < 12 || length > b.size() - at)
      return makeError("cmpt inner tile " + std::to_string(i) + " runs past the cmpt's end");
    tiles.push_back(b.substr(at, length));
    at += length;
  }
  return tiles;
}

}  // namespace hlod::tiles
