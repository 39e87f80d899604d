#pragma once
// The binary tile formats of 3D Tiles (CesiumGS/3d-tiles, specification/TileFormats): what a
// tile's content bytes are, and the glTF inside a Batched 3D Model (b3dm) or a Composite (cmpt).
// b3dm (3D Tiles 1.0; deprecated in 1.1, still read): a 28-byte header (magic "b3dm", version 1,
// byteLength, featureTableJSONByteLength, featureTableBinaryByteLength, batchTableJSONByteLength,
// batchTableBinaryByteLength), the feature table (JSON with BATCH_LENGTH and the optional
// RTC_CENTER, an array or a reference into its binary body), the batch table, then the GLB. The
// two legacy headers of early b3dm writers (20 bytes: batchLength, batchTableByteLength; 24
// bytes: batchTableJSONByteLength, batchTableBinaryByteLength, batchLength) are told apart as
// CesiumJS and cesium-native do: a "length" that reads as 0x22000000 or more is the start of
// the JSON or of the GLB. cmpt: magic "cmpt", version 1, byteLength, tilesLength, then the inner
// tiles, each with its own magic and byteLength.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "hlod/Result.h"

namespace hlod::tiles {

enum class TileFormat {
  Unknown,
  Glb,       // "glTF"
  GltfJson,  // glTF 2.0 JSON (an object with "asset" and no "root")
  Tileset,   // an external tileset (an object with "asset" and "root")
  B3dm,      // "b3dm"
  Cmpt,      // "cmpt"
  I3dm,      // "i3dm": instanced models (not imported)
  Pnts,      // "pnts": a point cloud (no triangles)
};

// What the bytes are, by their magic or, for JSON, the top-level keys. Reads at most the start
// of the bytes for binary formats; JSON is parsed (with the nesting bound of the glTF reader).
TileFormat detectTileFormat(std::string_view bytes);
const char* tileFormatName(TileFormat format);

// The glTF of a b3dm and what its feature table says about it.
struct B3dmContent {
  std::string_view glb;                 // a view into the b3dm's bytes
  std::optional<glm::dvec3> rtcCenter;  // RTC_CENTER: positions relative to it (tile frame)
  std::uint32_t batchLength = 0;        // BATCH_LENGTH (features: buildings, ...)
  std::uint32_t batchProperties = 0;    // batch table properties (kept by no one: counted)
};
// Every length is checked against the bytes before it is used; a table that is not a JSON
// object, a binary reference outside its body or a missing BATCH_LENGTH is an Error.
Result<B3dmContent> parseB3dm(std::string_view bytes);

// The inner tiles of a cmpt, as views into its bytes.
Result<std::vector<std::string_view>> parseCmpt(std::string_view bytes);

}  // namespace hlod::tiles
