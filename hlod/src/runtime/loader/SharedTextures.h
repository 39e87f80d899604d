#pragma once
// Reference counts of the texture sections nodes share (NodeInfo::textureOffset: the nodes of one
// level may share one texture section). A section is decoded once and held, with its image, while
// at least one resident node or load in progress uses it; the Loader counts its bytes once, from
// the first hold to the last release. Private to the loader (runtime/Loader.cpp); not locked: the
// Loader calls it under its mutex.
#include <cstdint>
#include <memory>
#include <unordered_map>

#include "hlod/Mesh.h"

namespace hlod {

class SharedTextures {
 public:
  bool held(std::uint64_t offset) const { return sections_.count(offset) > 0; }
  // The image a held section stands for (null while it is held only by loads in progress that did
  // not read it); null when it is not held.
  std::shared_ptr<const Image> image(std::uint64_t offset) const;
  // Resident nodes and loads in progress that hold it; 0 when it is not held.
  std::uint32_t users(std::uint64_t offset) const;
  // Adds a user. True when the section was not held before (its bytes come into memory); the
  // first holder's image stands for it.
  bool hold(std::uint64_t offset, const std::shared_ptr<const Image>& image);
  // Removes a user of a held section. True when it was the last (its bytes leave memory).
  bool release(std::uint64_t offset);

 private:
  struct Section {
    std::shared_ptr<const Image> image;
    std::uint32_t users = 0;
  };
  std::unordered_map<std::uint64_t, Section> sections_;  // by NodeInfo::textureOffset
};

}  // namespace hlod
