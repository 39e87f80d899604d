#include "hlod/store/NodeStore.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cassert>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>

namespace hlod {

namespace {

Result<std::vector<std::byte>> readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError("cannot open " + path.string());
  in.seekg(0, std::ios::end);
  const auto size = in.tellg();
  if (size < 0) return makeError("cannot read " + path.string());
  in.seekg(0);
  std::vector<std::byte> bytes(static_cast<std::size_t>(size));
  if (!in.read(reinterpret_cast<char*>(bytes.data()), size))
    return makeError("cannot read " + path.string());
  return bytes;
}

}  // namespace

Result<std::unique_ptr<NodeStore>> NodeStore::open(const std::filesystem::path& dir) {
  auto bytes = readWholeFile(dir / "skeleton.bin");
  if (!bytes) return makeError(dir.string() + " is not a node store: " + bytes.message());
  auto decoded = decodeSkeleton(*bytes);
  if (!decoded) return makeError(dir.string() + ": " + decoded.message());
  std::unique_ptr<NodeStore> store(new NodeStore());
  store->skeleton_ = std::move(decoded->skeleton);
  store->facts_ = decoded->facts;
  const auto payloadPath = dir / "payload.bin";
  store->fd_ = ::open(payloadPath.c_str(), O_RDONLY | O_CLOEXEC);
  if (store->fd_ < 0)
    return makeError("cannot open " + payloadPath.string() + ": " + std::strerror(errno));
  struct stat st {};
  if (::fstat(store->fd_, &st) != 0 || std::uint64_t(st.st_size) != store->facts_.payloadBytes)
    return makeError(payloadPath.string() + " has size " + std::to_string(st.st_size) +
                     ", the skeleton expects " + std::to_string(store->facts_.payloadBytes) +
                     " (truncated or from another build)");
  std::error_code ec;
  if (std::filesystem::exists(dir / "vdr.bin", ec)) {
    store->vdrFile_ = dir / "vdr.bin";
    auto entries = readVdrIndex(store->vdrFile_, std::uint32_t(store->skeleton_.nodes.size()));
    if (!entries) return makeError(dir.string() + ": " + entries.message());
    store->vdr_ = std::move(*entries);
  }
  return store;
}

Result<vdr::VdrObject> NodeStore::loadVdrObject(std::size_t i) const {
  if (i >= vdr_.size()) return makeError("no view-dependent object " + std::to_string(i));
  return readVdrObject(vdrFile_, vdr_[i]);
}

Result<std::shared_ptr<const vdr::VdrObject>> NodeStore::sharedVdrObject(std::size_t i) const {
  if (i >= vdr_.size()) return makeError("no view-dependent object " + std::to_string(i));
  {
    std::lock_guard lock(vdrMutex_);
    if (vdrObjects_.size() == vdr_.size() && vdrObjects_[i]) return vdrObjects_[i];
  }
  // Decoded outside the lock: two sessions may decode one object at once; the first kept wins.
  auto o = readVdrObject(vdrFile_, vdr_[i]);
  if (!o) return o.error();
  auto shared = std::make_shared<const vdr::VdrObject>(std::move(*o));
  std::lock_guard lock(vdrMutex_);
  vdrObjects_.resize(vdr_.size());
  if (!vdrObjects_[i]) vdrObjects_[i] = std::move(shared);
  return vdrObjects_[i];
}

NodeStore::~NodeStore() {
  if (fd_ >= 0) ::close(fd_);
}

namespace {

// Reads bytes [offset, offset + out.size()) of node n's stored payload from fd: the mesh
// section, then the texture section wherever it lies.
Status readStored(int fd, const NodeInfo& n, std::uint32_t node, std::uint64_t offset,
                  std::span<std::byte> out) {
  if (offset > n.payloadSize || out.size() > n.payloadSize - offset)
    return makeError("read outside the payload of node " + std::to_string(node));
  const auto readAt = [&](std::span<std::byte> into, std::uint64_t at) -> Status {
    std::size_t done = 0;
    while (done < into.size()) {
      const ssize_t got = ::pread(fd, into.data() + done, into.size() - done, off_t(at + done));
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) return makeError(std::string("reading payload.bin: ") + std::strerror(errno));
      if (got == 0) return makeError("payload.bin is shorter than the skeleton says (truncated)");
      done += std::size_t(got);
    }
    return Ok{};
  };
  const std::uint64_t mesh = n.meshSize();
  const std::size_t inMesh =
      offset < mesh ? std::size_t(std::min<std::uint64_t>(out.size(), mesh - offset)) : 0;
  if (inMesh > 0)
    if (auto s = readAt(out.first(inMesh), n.payloadOffset + offset); !s) return s;
  if (inMesh < out.size())
    return readAt(out.subspan(inMesh), n.textureOffset + (offset + inMesh - mesh));
  return Ok{};
}

// Checks and decodes node n's stored bytes: the whole payload, or its mesh section alone (a
// load for a scene without textures).
Result<LocalMesh> decodeStored(const NodeInfo& n, std::uint32_t node,
                               std::span<const std::byte> bytes) {
  const std::uint64_t meshSize = n.payloadSize - n.textureSize;
  const bool pixels = bytes.size() == n.payloadSize;
  if (!pixels && bytes.size() != meshSize)
    return makeError("payload of node " + std::to_string(node) + " has the wrong size");
  // The checksums cover the stored bytes: corruption is caught before decompression.
  const auto meshBytes = bytes.first(meshSize);
  if (crc32(meshBytes) != n.payloadChecksum ||
      (pixels && n.textureSize > 0 && crc32(bytes.subspan(meshSize)) != n.textureChecksum))
    return makeError("node " + std::to_string(node) +
                     ": payload checksum mismatch (corrupt store)");
  auto raw = inflatePayload(meshBytes, n.memoryBytes - n.textureBytes);
  if (!raw) return makeError("node " + std::to_string(node) + ": " + raw.message());
  if (pixels && n.textureSize > 0) {
    auto texture = inflatePayload(bytes.subspan(meshSize), n.textureBytes);
    if (!texture) return makeError("node " + std::to_string(node) + ": " + texture.message());
    raw->insert(raw->end(), texture->begin(), texture->end());
  }
  auto mesh = decodePayloadBytes(*raw, n.centre, pixels);
  if (!mesh) return makeError("node " + std::to_string(node) + ": " + mesh.message());
  // What the selectors plan with, from the skeleton, must be what the payload can draw.
  if (mesh->triangleCount() != n.numTri ||
      mesh->progression.decimated() != (n.progressive() ? n.numTri - n.minTri : 0) ||
      mesh->splats.size() != n.splatCount)
    return makeError("node " + std::to_string(node) +
                     ": payload disagrees with the skeleton (triangles, progression or splats)");
  return mesh;
}

}  // namespace

Status NodeStore::readPayloadChunk(std::uint32_t node, std::uint64_t offset,
                                   std::span<std::byte> out) const {
  if (node >= skeleton_.nodes.size()) return makeError("no node " + std::to_string(node));
  return readStored(fd_, skeleton_.nodes[node], node, offset, out);
}

Result<LocalMesh> NodeStore::decodePayload(std::uint32_t node,
                                           std::span<const std::byte> bytes) const {
  if (node >= skeleton_.nodes.size()) return makeError("no node " + std::to_string(node));
  return decodeStored(skeleton_.nodes[node], node, bytes);
}

Result<LocalMesh> NodeStore::loadNode(std::uint32_t node) const {
  if (node >= skeleton_.nodes.size()) return makeError("no node " + std::to_string(node));
  std::vector<std::byte> bytes(skeleton_.nodes[node].payloadSize);
  if (auto s = readPayloadChunk(node, 0, bytes); !s) return s.error();
  return decodePayload(node, bytes);
}

Status checkReplaceableStore(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(dir, ec);
  if (st.type() == fs::file_type::not_found) return Ok{};
  if (st.type() != fs::file_type::directory)
    return makeError(dir.string() + " exists and is not a node store folder; not replacing it");
  // A store holds exactly the files a build writes, and its skeleton starts with the magic.
  // Anything else there is the user's: never delete it.
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if ((name != "skeleton.bin" && name != "payload.bin" && name != "vdr.bin") ||
        !entry.is_regular_file(ec))
      return makeError(dir.string() + " holds " + name +
                       ", which is not part of a node store; not replacing the folder "
                       "(give another -o, or remove it yourself)");
  }
  if (ec) return makeError("cannot list " + dir.string() + ": " + ec.message());
  if (fs::is_empty(dir, ec)) return Ok{};
  std::ifstream in(dir / "skeleton.bin", std::ios::binary);
  char magic[8] = {};
  if (!in.read(magic, sizeof magic) || std::memcmp(magic, "HLODSKEL", sizeof magic) != 0)
    return makeError((dir / "skeleton.bin").string() +
                     " is not a node store's skeleton; not replacing " + dir.string());
  return Ok{};
}

namespace {

// A new sibling folder named stem.suffix-N that did not exist before (created here, so
// removing it later removes only what this build wrote).
Result<std::filesystem::path> createUniqueSibling(const std::filesystem::path& dir,
                                                  const char* suffix) {
  std::random_device rd;
  std::error_code ec;
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::filesystem::path p = dir;
    p += std::string(suffix) + std::to_string(rd() % 1000000);
    if (std::filesystem::create_directory(p, ec)) return p;
    if (ec) return makeError("cannot create " + p.string() + ": " + ec.message());
  }
  return makeError("cannot find a free temporary name beside " + dir.string());
}

}  // namespace

Result<std::unique_ptr<NodeStoreWriter>> NodeStoreWriter::create(const std::filesystem::path& dir) {
  // Refuse before the build starts, not after it has run for minutes.
  if (auto ok = checkReplaceableStore(dir); !ok) return ok.error();
  std::unique_ptr<NodeStoreWriter> w(new NodeStoreWriter());
  w->dir_ = dir;
  std::error_code ec;
  if (dir.has_parent_path()) std::filesystem::create_directories(dir.parent_path(), ec);
  auto tmp = createUniqueSibling(dir, ".tmp-");
  if (!tmp) return tmp.error();
  w->tmp_ = *tmp;
  // Read too: cell nodes are built from the hlod_0 payloads already written (readBack).
  w->payload_ = std::fopen((w->tmp_ / "payload.bin").c_str(), "w+b");
  if (!w->payload_) return makeError("cannot create " + (w->tmp_ / "payload.bin").string());
  return w;
}

NodeStoreWriter::~NodeStoreWriter() {
  if (payload_) std::fclose(payload_);
  if (vdr_) std::fclose(vdr_);
  if (!finished_) {
    std::error_code ec;
    std::filesystem::remove_all(tmp_, ec);
  }
}

StoredPayload storePayload(const LocalMesh& mesh, bool withTexture) {
  const std::vector<std::byte> raw = encodePayload(mesh);
  // The pixels end the payload (see the format): they become a section of their own, so that
  // a scene without textures reads, inflates and keeps none of them.
  const bool textured =
      mesh.texture && !mesh.texture->empty() &&
      mesh.texture->pixels.size() == std::size_t(mesh.texture->width) * mesh.texture->height * 4;
  const std::size_t pixelBytes = textured ? mesh.texture->pixels.size() : 0;
  const std::span<const std::byte> all(raw);
  StoredPayload p;
  p.mesh = compressPayload(all.first(raw.size() - pixelBytes));
  if (pixelBytes && withTexture) p.texture = compressPayload(all.last(pixelBytes));
  p.memoryBytes = raw.size();
  p.textureBytes = pixelBytes;
  return p;
}

Status NodeStoreWriter::appendPayload(const LocalMesh& mesh, NodeInfo& node) {
  return appendStored(storePayload(mesh), node);
}

Status NodeStoreWriter::appendStored(const StoredPayload& payload, NodeInfo& node) {
  assert(payload.textureBytes == 0 || !payload.texture.empty());
  for (const auto* section : {&payload.mesh, &payload.texture})
    if (std::fwrite(section->data(), 1, section->size(), payload_) != section->size())
      return makeError("cannot write payload.bin (disk full?)");
  node.payloadOffset = payloadBytes_;
  node.payloadSize = payload.mesh.size() + payload.texture.size();
  node.payloadChecksum = crc32(payload.mesh);
  node.memoryBytes = payload.memoryBytes;
  node.textureOffset = payload.texture.empty() ? 0 : payloadBytes_ + payload.mesh.size();
  node.textureSize = payload.texture.size();
  node.textureChecksum = payload.textureBytes ? crc32(payload.texture) : 0;
  node.textureBytes = payload.textureBytes;
  payloadBytes_ += node.payloadSize;
  return Ok{};
}

Status NodeStoreWriter::appendSharingTexture(const StoredPayload& payload, const NodeInfo& owner,
                                             NodeInfo& node) {
  assert(payload.texture.empty() && payload.textureBytes == owner.textureBytes &&
         owner.textureSize > 0);
  if (std::fwrite(payload.mesh.data(), 1, payload.mesh.size(), payload_) != payload.mesh.size())
    return makeError("cannot write payload.bin (disk full?)");
  node.payloadOffset = payloadBytes_;
  node.payloadSize = payload.mesh.size() + owner.textureSize;
  node.payloadChecksum = crc32(payload.mesh);
  node.memoryBytes = payload.memoryBytes;
  node.textureOffset = owner.textureOffset;
  node.textureSize = owner.textureSize;
  node.textureChecksum = owner.textureChecksum;
  node.textureBytes = owner.textureBytes;
  payloadBytes_ += payload.mesh.size();
  return Ok{};
}

Status NodeStoreWriter::flush() {
  if (std::fflush(payload_) != 0) return makeError("cannot write payload.bin (disk full?)");
  return Ok{};
}

Result<LocalMesh> NodeStoreWriter::readBack(const NodeInfo& node) const {
  std::vector<std::byte> bytes(node.payloadSize);
  if (auto s = readStored(fileno(payload_), node, 0, 0, bytes); !s) return s.error();
  return decodeStored(node, 0, bytes);
}

Status NodeStoreWriter::appendVdr(StoredVdr&& object, std::uint32_t rootNode) {
  if (!vdr_) {
    vdr_ = std::fopen((tmp_ / "vdr.bin").c_str(), "wb");
    if (!vdr_) return makeError("cannot create " + (tmp_ / "vdr.bin").string());
  }
  if (std::fwrite(object.bytes.data(), 1, object.bytes.size(), vdr_) != object.bytes.size())
    return makeError("cannot write vdr.bin (disk full?)");
  object.entry.rootNode = rootNode;
  object.entry.offset = vdrBytes_;
  vdrBytes_ += object.bytes.size();
  vdrEntries_.push_back(object.entry);
  return Ok{};
}

Status NodeStoreWriter::finish(const Skeleton& skeleton, StoreFacts facts) {
  if (vdr_) {
    const std::vector<std::byte> index = encodeVdrIndex(vdrEntries_, vdrBytes_);
    const bool written = std::fwrite(index.data(), 1, index.size(), vdr_) == index.size() &&
                         std::fflush(vdr_) == 0 && ::fsync(fileno(vdr_)) == 0;
    std::fclose(vdr_);
    vdr_ = nullptr;
    if (!written) return makeError("cannot write vdr.bin (disk full?)");
  }
  facts.payloadBytes = payloadBytes_;
  const bool flushed = std::fflush(payload_) == 0 && ::fsync(fileno(payload_)) == 0;
  std::fclose(payload_);
  payload_ = nullptr;
  if (!flushed) return makeError("cannot write payload.bin (disk full?)");
  const auto bytes = encodeSkeleton(skeleton, facts);
  {
    std::ofstream out(tmp_ / "skeleton.bin", std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    out.close();
    if (!out) return makeError("cannot write skeleton.bin");
  }
  // Replace an earlier store, but never some other folder the user named by mistake (it may
  // have appeared during the build). The old store is moved aside first and removed only once
  // the new one is in place, so an interrupted finish leaves one of them whole.
  if (auto ok = checkReplaceableStore(dir_); !ok) return ok.error();
  std::error_code ec;
  std::filesystem::path old;
  if (std::filesystem::exists(dir_, ec)) {
    auto aside = createUniqueSibling(dir_, ".old-");
    if (!aside) return aside.error();
    old = *aside;
    std::filesystem::remove(old, ec);  // the empty folder just made: rename needs the name free
    std::filesystem::rename(dir_, old, ec);
    if (ec)
      return makeError("cannot move the earlier store " + dir_.string() +
                       " aside: " + ec.message());
  }
  std::filesystem::rename(tmp_, dir_, ec);
  if (ec) {
    std::error_code back;
    if (!old.empty()) std::filesystem::rename(old, dir_, back);
    return makeError("cannot move the store into place at " + dir_.string() + ": " + ec.message());
  }
  if (!old.empty()) {
    // Only what checkReplaceableStore saw: skeleton.bin, payload.bin and vdr.bin.
    std::filesystem::remove(old / "skeleton.bin", ec);
    std::filesystem::remove(old / "payload.bin", ec);
    std::filesystem::remove(old / "vdr.bin", ec);
    std::filesystem::remove(old, ec);
  }
  finished_ = true;
  return Ok{};
}

}  // namespace hlod
