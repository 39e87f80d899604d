#pragma once
// Files written whole or not at all: the bytes go to a temporary name beside the file, every
// write, the flush and the close checked, and are then renamed over it. A full disk or a killed
// process leaves the file as it was (or absent), never truncated: a torn frame_00000.png or an
// empty stats.json read as valid output.
#include <filesystem>
#include <string_view>

#include "hlod/Result.h"

namespace hlod {

// An Error names the file and the reason; the temporary file is removed again.
Status writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

}  // namespace hlod
