// Implicit tiling subtrees: hlod/tiles/Subtree.h (3D Tiles 1.1 ImplicitTiling, "Subtree JSON
// Format", "Subtree Binary Format", "Availability").
#include "hlod/tiles/Subtree.h"

#include <cstring>

#include <nlohmann/json.hpp>

#include "hlod/JsonDepth.h"

namespace hlod::tiles {

namespace {

constexpr std::size_t kMaxSubtreeJsonDepth = 128;

std::uint64_t power(std::uint64_t base, unsigned exponent) {
  std::uint64_t v = 1;
  for (unsigned i = 0; i < exponent; ++i) v *= base;
  return v;
}

struct Buffers {
  std::vector<std::string> data;  // each buffer's bytes
};

// One availability object: a constant, or a bitstream (a buffer view) of `length` elements.
Result<Availability> availability(const nlohmann::json& j, std::uint64_t length,
                                  const nlohmann::json& views, const Buffers& buffers,
                                  const std::string& what) {
  if (!j.is_object()) return makeError(what + " is not an object");
  Availability a;
  a.length = length;
  const bool hasConstant = j.contains("constant"), hasBits = j.contains("bitstream");
  // availability.schema.json: exactly one of the two.
  if (hasConstant == hasBits) return makeError(what + " needs either constant or bitstream");
  if (hasConstant) {
    if (!j["constant"].is_number_integer()) return makeError(what + ".constant is not 0 or 1");
    const auto c = j["constant"].get<std::int64_t>();
    if (c != 0 && c != 1) return makeError(what + ".constant is not 0 or 1");
    a.value = c == 1;
    return a;
  }
  if (!j["bitstream"].is_number_unsigned()) return makeError(what + ".bitstream is not an index");
  const auto v = j["bitstream"].get<std::uint64_t>();
  if (!views.is_array() || v >= views.size())
    return makeError(what + ".bitstream names no buffer view");
  const nlohmann::json& view = views[v];
  if (!view.is_object() || !view.contains("buffer") || !view["buffer"].is_number_unsigned() ||
      !view.contains("byteLength") || !view["byteLength"].is_number_unsigned() ||
      (view.contains("byteOffset") && !view["byteOffset"].is_number_unsigned()))
    return makeError("buffer view " + std::to_string(v) + " is malformed");
  const auto b = view["buffer"].get<std::uint64_t>();
  const auto offset = view.value("byteOffset", std::uint64_t(0));
  const auto size = view["byteLength"].get<std::uint64_t>();
  if (b >= buffers.data.size())
    return makeError("buffer view " + std::to_string(v) + " names no buffer");
  const std::string& buffer = buffers.data[b];
  if (offset > buffer.size() || size > buffer.size() - offset)
    return makeError("buffer view " + std::to_string(v) + " lies outside its buffer");
  if (size < (length + 7) / 8)
    return makeError(what + ": its bitstream holds " + std::to_string(size) + " bytes, " +
                     std::to_string((length + 7) / 8) + " are needed");
  a.constant = false;
  a.bits.assign(buffer.begin() + std::ptrdiff_t(offset),
                buffer.begin() + std::ptrdiff_t(offset + (length + 7) / 8));
  return a;
}

}  // namespace

std::uint64_t mortonIndex(std::uint32_t x, std::uint32_t y) {
  std::uint64_t m = 0;
  for (unsigned b = 0; b < 32; ++b)
    m |= (std::uint64_t((x >> b) & 1u) << (2 * b)) | (std::uint64_t((y >> b) & 1u) << (2 * b + 1));
  return m;
}

std::uint64_t mortonIndex(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  std::uint64_t m = 0;
  for (unsigned b = 0; b < 21; ++b)
    m |= (std::uint64_t((x >> b) & 1u) << (3 * b)) | (std::uint64_t((y >> b) & 1u) << (3 * b + 1)) |
         (std::uint64_t((z >> b) & 1u) << (3 * b + 2));
  return m;
}

std::string expandTemplate(std::string_view uri, std::uint32_t level, std::uint32_t x,
                           std::uint32_t y, std::uint32_t z) {
  std::string out;
  for (std::size_t i = 0; i < uri.size();) {
    const auto take = [&](std::string_view key, std::uint32_t value) {
      if (uri.substr(i, key.size()) != key) return false;
      out += std::to_string(value);
      i += key.size();
      return true;
    };
    if (take("{level}", level) || take("{x}", x) || take("{y}", y) || take("{z}", z)) continue;
    out.push_back(uri[i++]);
  }
  return out;
}

Result<Subtree> parseSubtree(std::string_view bytes, unsigned branching, unsigned levels,
                             const SubtreeBufferLoader& loadBuffer) {
  if (branching != 4 && branching != 8) return makeError("subdivision is neither 4 nor 8 ways");
  if (levels < 1 || (branching == 4 && levels > 16) || (branching == 8 && levels > 10))
    return makeError("subtreeLevels " + std::to_string(levels) + " out of range (1.." +
                     (branching == 4 ? "16" : "10") + ")");
  std::string_view json = bytes;
  Buffers buffers;
  std::string_view internal;
  bool binary = false;
  if (bytes.size() >= 4 && std::memcmp(bytes.data(), "subt", 4) == 0) {
    // Binary: a 24-byte header, the JSON, then the binary chunk.
    binary = true;
    if (bytes.size() < 24) return makeError("subtree header truncated");
    std::uint32_t version;
    std::uint64_t jsonLength, binLength;
    std::memcpy(&version, bytes.data() + 4, 4);
    std::memcpy(&jsonLength, bytes.data() + 8, 8);
    std::memcpy(&binLength, bytes.data() + 16, 8);
    if (version != 1) return makeError("subtree version " + std::to_string(version) + " (only 1)");
    if (jsonLength > bytes.size() - 24 || binLength > bytes.size() - 24 - jsonLength)
      return makeError("subtree truncated: its header claims more bytes than the file has");
    json = bytes.substr(24, jsonLength);
    internal = bytes.substr(24 + jsonLength, binLength);
  }
  while (!json.empty() && (json.back() == ' ' || json.back() == '\0')) json.remove_suffix(1);
  if (jsonDepth(json, kMaxSubtreeJsonDepth) > kMaxSubtreeJsonDepth)
    return makeError("subtree JSON nested too deep");
  const nlohmann::json j = nlohmann::json::parse(json, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return makeError("subtree JSON is not an object");
  if (j.contains("buffers")) {
    const nlohmann::json& list = j["buffers"];
    if (!list.is_array()) return makeError("subtree buffers is not an array");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const nlohmann::json& b = list[i];
      const std::string what = "subtree buffer " + std::to_string(i);
      if (!b.is_object() || !b.contains("byteLength") || !b["byteLength"].is_number_unsigned())
        return makeError(what + " has no byteLength");
      const auto length = b["byteLength"].get<std::uint64_t>();
      std::string data;
      if (b.contains("uri")) {
        if (!b["uri"].is_string()) return makeError(what + ".uri is not a string");
        auto loaded = loadBuffer(b["uri"].get<std::string>());
        if (!loaded) return makeError(what + ": " + loaded.message());
        data = std::move(*loaded);
      } else if (binary && i == 0) {
        data = std::string(internal);  // the internal buffer: the binary chunk
      } else {
        return makeError(what + " has no uri and is not the binary chunk");
      }
      if (data.size() < length)
        return makeError(what + " holds " + std::to_string(data.size()) + " bytes, " +
                         std::to_string(length) + " claimed");
      data.resize(length);
      buffers.data.push_back(std::move(data));
    }
  }
  const nlohmann::json views = j.value("bufferViews", nlohmann::json::array());
  const std::uint64_t children = power(branching, levels);
  const std::uint64_t tiles = (children - 1) / (branching - 1);
  Subtree s;
  if (!j.contains("tileAvailability")) return makeError("subtree has no tileAvailability");
  if (!j.contains("childSubtreeAvailability"))
    return makeError("subtree has no childSubtreeAvailability");
  auto t = availability(j["tileAvailability"], tiles, views, buffers, "tileAvailability");
  if (!t) return t.error();
  if (t->constant && !t->value)
    return makeError("tileAvailability.constant 0: a subtree without tiles");
  if (!t->at(0)) return makeError("tileAvailability: the subtree's root tile is not available");
  s.tiles = std::move(*t);
  auto c = availability(j["childSubtreeAvailability"], children, views, buffers,
                        "childSubtreeAvailability");
  if (!c) return c.error();
  s.childSubtrees = std::move(*c);
  if (j.contains("contentAvailability")) {
    const nlohmann::json& list = j["contentAvailability"];
    if (!list.is_array()) return makeError("contentAvailability is not an array");
    for (std::size_t i = 0; i < list.size(); ++i) {
      auto a = availability(list[i], tiles, views, buffers,
                            "contentAvailability[" + std::to_string(i) + "]");
      if (!a) return a.error();
      s.contents.push_back(std::move(*a));
    }
  }
  return s;
}

}  // namespace hlod::tiles
