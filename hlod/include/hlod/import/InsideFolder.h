#pragma once
// Confines the files a model refers to (materials, textures, buffers, city blocks) to the model's
// own folder: a model from someone else must not make hlodr read, or report on, other files of
// the machine (docs/architecture.md, Formats).
#include <filesystem>
#include <string>

#include "hlod/Result.h"

namespace hlod {

// The file that `reference` (as written in a model file: relative to `folder`, '/' separated)
// names, when it lies inside `folder` or below it once every symbolic link on the way is
// resolved; the returned path has those links resolved, so opening it opens what was checked.
// An Error for an absolute reference, one that climbs out with "..", or one through a link that
// leaves the folder or leads nowhere. The message names the reference and the folder only: it
// says nothing about the outside file, not even whether it exists. Whether the returned file
// exists is the caller's question.
Result<std::filesystem::path> insideFolder(const std::filesystem::path& folder,
                                           const std::string& reference);

}  // namespace hlod
