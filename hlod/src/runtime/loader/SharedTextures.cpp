// Reference counts of shared texture sections (runtime/loader/SharedTextures.h).
#include "runtime/loader/SharedTextures.h"

#include <cassert>

namespace hlod {

std::shared_ptr<const Image> SharedTextures::image(std::uint64_t offset) const {
  auto it = sections_.find(offset);
  return it != sections_.end() ? it->second.image : nullptr;
}

std::uint32_t SharedTextures::users(std::uint64_t offset) const {
  auto it = sections_.find(offset);
  return it != sections_.end() ? it->second.users : 0;
}

bool SharedTextures::hold(std::uint64_t offset, const std::shared_ptr<const Image>& image) {
  auto [it, fresh] = sections_.try_emplace(offset);
  if (fresh) it->second.image = image;
  ++it->second.users;
  return fresh;
}

bool SharedTextures::release(std::uint64_t offset) {
  auto it = sections_.find(offset);
  assert(it != sections_.end() && it->second.users > 0);
  if (--it->second.users > 0) return false;
  sections_.erase(it);
  return true;
}

}  // namespace hlod
