#pragma once
// Shared helpers of the mesh readers: whole-file reading, a fast text scanner with line numbers
// (std::from_chars, no iostreams), error messages that begin with the file path, and endian-aware
// binary reads. Private to hlod/src/import.
#include <bit>
#include <cassert>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "hlod/Mesh.h"
#include "hlod/Result.h"
#include "hlod/import/Import.h"

namespace hlod::import {

// "PATH: what" -- every import error names the file first.
inline Error fileError(const std::filesystem::path& path, const std::string& what) {
  return makeError(path.string() + ": " + what);
}
inline Error lineError(const std::filesystem::path& path, std::size_t line,
                       const std::string& what) {
  return makeError(path.string() + ": line " + std::to_string(line) + ": " + what);
}

// Reads the whole file: parsing from memory is much faster than stream extraction.
Result<std::string> readWholeFile(const std::filesystem::path& path);

// Warnings (a missing texture) go to the Model's warnings (importModel collects them); they
// never fail the import.
void warn(const std::filesystem::path& path, const std::string& what);

// Loads a texture named by a mesh file, relative to that file's folder; a failure is a warning and
// gives null. Identical paths share one Image through the cache.
class TextureCache {
 public:
  std::shared_ptr<const Image> load(const std::filesystem::path& meshFile, const std::string& name);

 private:
  std::vector<std::pair<std::filesystem::path, std::shared_ptr<const Image>>> loaded_;
};

// Fast forward-only scanner over text with line counting.
class TextScanner {
 public:
  explicit TextScanner(std::string_view text) : p_(text.data()), end_(text.data() + text.size()) {}

  // Invariant: p_ <= end_: every move below stops at end_ (the one that did not, advance(), is
  // gone). remaining() says so to the compiler too: g++ -O3 could not rule out a wrapped count
  // reaching memchr and failed the Release build with stringop-overread.
  bool atEnd() const { return p_ >= end_; }
  std::size_t line() const { return line_; }
  const char* position() const { return p_; }
  std::size_t remaining() const {
    assert(p_ <= end_);
    return p_ < end_ ? static_cast<std::size_t>(end_ - p_) : 0;
  }

  // Skips spaces and tabs (and \r) on the current line.
  void skipBlanks() {
    while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\f' || *p_ == '\v'))
      ++p_;
  }
  // True at end of line or end of text (after blanks).
  bool atEol() {
    skipBlanks();
    return p_ >= end_ || *p_ == '\n';
  }
  // Skips whitespace including newlines, and comments from `comment` to end of line.
  void skipSpace(char comment = '\0') {
    while (p_ < end_) {
      char c = *p_;
      if (c == '\n') {
        ++line_;
        ++p_;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++p_;
      } else if (comment != '\0' && c == comment) {
        skipLine();
      } else {
        break;
      }
    }
  }
  // Moves past the next newline.
  void skipLine() {
    const void* nl = std::memchr(p_, '\n', remaining());
    if (!nl) {
      p_ = end_;
      return;
    }
    p_ = static_cast<const char*>(nl) + 1;
    ++line_;
  }
  // The rest of the current line (without \r\n), and moves past it.
  std::string_view restOfLine() {
    skipBlanks();
    const char* start = p_;
    const void* nl = std::memchr(p_, '\n', remaining());
    const char* stop = nl ? static_cast<const char*>(nl) : end_;
    p_ = stop;
    if (p_ < end_) {
      ++p_;
      ++line_;
    }
    while (stop > start && (stop[-1] == '\r' || stop[-1] == ' ' || stop[-1] == '\t')) --stop;
    return {start, static_cast<std::size_t>(stop - start)};
  }
  // The next token on the current line (empty at end of line).
  std::string_view token() {
    skipBlanks();
    const char* start = p_;
    while (p_ < end_ && !isSpace(*p_)) ++p_;
    return {start, static_cast<std::size_t>(p_ - start)};
  }
  // Parses a number on the current line; false if none (no consumption then).
  bool number(double& out) {
    skipBlanks();
    const char* s = p_;
    if (s < end_ && *s == '+') ++s;
    auto [ptr, ec] = std::from_chars(s, end_, out);
    if (ec == std::errc::result_out_of_range) {
      // Denormal or huge literal: let strtod decide (gives 0 or inf; inf is caught later).
      std::string tmp(s, static_cast<std::size_t>(ptr - s));
      out = std::strtod(tmp.c_str(), nullptr);
    } else if (ec != std::errc()) {
      return false;
    }
    if (ptr < end_ && !isSpace(*ptr) && *ptr != '/' && *ptr != '#') return false;
    p_ = ptr;
    return true;
  }
  bool integer(long long& out) {
    skipBlanks();
    const char* s = p_;
    if (s < end_ && *s == '+') ++s;
    auto [ptr, ec] = std::from_chars(s, end_, out);
    if (ec != std::errc()) return false;
    if (ptr < end_ && !isSpace(*ptr) && *ptr != '/' && *ptr != '#') return false;
    p_ = ptr;
    return true;
  }
  // Like number()/integer() but also crosses newlines (formats where values may wrap lines).
  bool numberAcrossLines(double& out, char comment = '\0') {
    skipSpace(comment);
    return number(out);
  }
  bool integerAcrossLines(long long& out, char comment = '\0') {
    skipSpace(comment);
    return integer(out);
  }
  static bool isSpace(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
  }

 private:
  const char* p_;
  const char* end_;
  std::size_t line_ = 1;
};

// Binary reading of one scalar of type T stored little- or big-endian.
template <class T>
inline T loadScalar(const char* p, bool bigEndian) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (bigEndian != (std::endian::native == std::endian::big)) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  }
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

// Mixes 64 bits so that the low bits of a hash are usable for a power-of-two table.
inline std::uint64_t mixBits(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xBF58476D1CE4E5B9ULL;
  x ^= x >> 27;
  x *= 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// Open-addressing map from a key to a 32-bit vertex index: the vertex welding of STL and the
// (v, vt, vn) sharing of OBJ do millions of lookups, where node-based maps spend most of their
// time in malloc.
template <class Key, class Hash>
class FlatIndexMap {
 public:
  FlatIndexMap() : FlatIndexMap(16) {}
  explicit FlatIndexMap(std::size_t expected) { rehash(capacityFor(expected)); }

  // The index stored for key, inserting `value` when absent; second is true on insertion.
  std::pair<std::uint32_t, bool> insert(const Key& key, std::uint32_t value) {
    if ((size_ + 1) * 2 > slots_.size()) rehash(slots_.size() * 2);
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = Hash{}(key)&mask;; i = (i + 1) & mask) {
      Slot& s = slots_[i];
      if (s.value == kEmpty) {
        s.key = key;
        s.value = value;
        ++size_;
        return {value, true};
      }
      if (s.key == key) return {s.value, false};
    }
  }
  void clear() {
    slots_.clear();
    slots_.shrink_to_fit();
    size_ = 0;
  }

 private:
  static constexpr std::uint32_t kEmpty = 0xffffffffu;
  struct Slot {
    Key key{};
    std::uint32_t value = kEmpty;
  };
  static std::size_t capacityFor(std::size_t n) {
    std::size_t c = 16;
    while (c < n * 2) c *= 2;
    return c;
  }
  void rehash(std::size_t capacity) {
    std::vector<Slot> old(capacity);
    old.swap(slots_);
    size_ = 0;
    for (const Slot& s : old)
      if (s.value != kEmpty) insert(s.key, s.value);
  }
  std::vector<Slot> slots_;
  std::size_t size_ = 0;
};

// The per-format readers; each returns an unvalidated Model (importModel validates).
Result<Model> readPly(const std::filesystem::path& path, const std::string& bytes);
Result<Model> readOff(const std::filesystem::path& path, const std::string& bytes);
Result<Model> readStl(const std::filesystem::path& path, const std::string& bytes);
Result<Model> readObj(const std::filesystem::path& path, const std::string& bytes);
Result<Model> readGltf(const std::filesystem::path& path, bool binary);
Result<GltfContent> readGltfBytes(const GltfBytes& in);
Result<Model> readCityJson(const std::filesystem::path& path, const std::string& bytes,
                           const ImportOptions& options);
// True when JSON text has the member "type": "CityJSON" (anywhere: members are unordered).
bool looksLikeCityJson(std::string_view bytes);

}  // namespace hlod::import
