#pragma once
// Nesting depth of JSON text, measured before a parser recurses into it: the glTF reader and the
// CityJSON reader refuse files nested deeper than they can be (20,000 brackets overflowed
// tinygltf's stack). Private to hlod/src/import.
#include <cstddef>

namespace hlod::import {

// The deepest nesting of arrays and objects in JSON text, strings skipped; stops counting once
// past `limit`.
std::size_t jsonDepth(const char* text, std::size_t size, std::size_t limit);

}  // namespace hlod::import
