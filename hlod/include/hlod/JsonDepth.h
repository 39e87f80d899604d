#pragma once
// Nesting depth of JSON text, measured before a parser recurses into it: the glTF and CityJSON
// readers, scene files and the service's request bodies refuse text nested deeper than they can
// be (20,000 brackets overflowed tinygltf's stack).
#include <cstddef>
#include <string_view>

namespace hlod {

// The deepest nesting of arrays and objects in JSON text, strings skipped; stops counting once
// past `limit`.
std::size_t jsonDepth(const char* text, std::size_t size, std::size_t limit);
inline std::size_t jsonDepth(std::string_view text, std::size_t limit) {
  return jsonDepth(text.data(), text.size(), limit);
}

}  // namespace hlod
