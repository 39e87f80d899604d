#include "server/GlMemory.h"

namespace service::server {

GlMemory::Lease& GlMemory::Lease::operator=(Lease&& o) noexcept {
  if (this != &o) {
    release();
    owner_ = o.owner_;
    bytes_ = o.bytes_;
    o.owner_ = nullptr;
  }
  return *this;
}

void GlMemory::Lease::resize(std::uint64_t bytes) {
  if (!owner_) return;
  std::lock_guard lock(owner_->mutex_);
  owner_->used_ = owner_->used_.load() - bytes_ + bytes;
  bytes_ = bytes;
}

void GlMemory::Lease::release() {
  if (!owner_) return;
  {
    std::lock_guard lock(owner_->mutex_);
    owner_->used_ = owner_->used_.load() - bytes_;
  }
  owner_ = nullptr;
  bytes_ = 0;
}

std::optional<GlMemory::Lease> GlMemory::reserve(std::uint64_t bytes) {
  std::lock_guard lock(mutex_);
  if (cap_ > 0 && used_.load() + bytes > cap_) return std::nullopt;
  used_ = used_.load() + bytes;
  return Lease(this, bytes);
}

}  // namespace service::server
