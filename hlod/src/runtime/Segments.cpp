// Segments of a path run: ranges, the "i/N" argument, the join's checks. See Segments.h.
#include "hlod/runtime/Segments.h"

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <numeric>

namespace hlod {

FrameRange segmentRange(std::uint64_t total, std::uint32_t index, std::uint32_t count) {
  assert(count > 0 && index < count);
  // floor(F*k/N) without overflowing F*k: F = q*N + r, and r*k < 2^64 as r < N < 2^32.
  const std::uint64_t q = total / count, r = total % count;
  auto at = [&](std::uint64_t k) { return q * k + r * k / count; };
  return {at(index), at(std::uint64_t{index} + 1)};
}

namespace {

bool parseWhole(const std::string& s, std::uint64_t& out) {
  if (s.empty() || s.size() > 9) return false;  // more digits than any allowed count
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc{} && p == s.data() + s.size();
}

}  // namespace

Result<SegmentSpec> parseSegment(const std::string& text) {
  const std::size_t slash = text.find('/');
  std::uint64_t i = 0, n = 0;
  if (slash == std::string::npos || !parseWhole(text.substr(0, slash), i) ||
      !parseWhole(text.substr(slash + 1), n))
    return makeError("--segment needs I/N, two whole numbers (e.g. 0/2), not '" + text + "'");
  if (n < 1 || n > kMaxSegments)
    return makeError("--segment " + text + ": N must be in 1.." + std::to_string(kMaxSegments));
  if (i >= n)
    return makeError("--segment " + text + ": I counts from 0 and must be below N (0.." +
                     std::to_string(n - 1) + ")");
  return SegmentSpec{static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(n)};
}

Result<std::vector<std::size_t>> segmentOrder(const std::vector<SegmentPart>& parts) {
  if (parts.empty()) return makeError("no parts to join");
  const SegmentPart& a = parts.front();
  for (const SegmentPart& p : parts) {
    if (p.spec.count != a.spec.count || p.runFrames != a.runFrames)
      return makeError(p.name + " is segment " + std::to_string(p.spec.index) + "/" +
                       std::to_string(p.spec.count) + " of " + std::to_string(p.runFrames) +
                       " frames, " + a.name + " of a split into " + std::to_string(a.spec.count) +
                       " of " + std::to_string(a.runFrames) + ": not parts of one run");
    if (p.width != a.width || p.height != a.height)
      return makeError(p.name + " is " + std::to_string(p.width) + "x" + std::to_string(p.height) +
                       ", " + a.name + " " + std::to_string(a.width) + "x" +
                       std::to_string(a.height) + ": frame sizes differ");
    if (!(std::abs(p.fps - a.fps) <= 1e-9 * a.fps))
      return makeError(p.name + " and " + a.name + " have different frame rates (" +
                       std::to_string(p.fps) + " and " + std::to_string(a.fps) + " fps)");
    if (p.frames.size() != p.range.end - p.range.first)
      return makeError(p.name + " holds " + std::to_string(p.frames.size()) +
                       " frames, its range [" + std::to_string(p.range.first) + ", " +
                       std::to_string(p.range.end) + ") " +
                       std::to_string(p.range.end - p.range.first) + ": an unfinished segment");
    for (std::size_t k = 0; k < p.frames.size(); ++k)
      if (p.frames[k].index != p.range.first + k)
        return makeError(p.name + ": frame " + std::to_string(k) + " is numbered " +
                         std::to_string(p.frames[k].index) + ", not " +
                         std::to_string(p.range.first + k));
  }
  std::vector<std::size_t> order(parts.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return parts[x].range.first < parts[y].range.first;
  });
  std::uint64_t next = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const SegmentPart& p = parts[order[k]];
    if (p.range.first > next)
      return makeError("frames " + std::to_string(next) + ".." + std::to_string(p.range.first - 1) +
                       " are missing (a gap before " + p.name + ", segment " +
                       std::to_string(p.spec.index) + ")");
    if (p.range.first < next)
      return makeError(p.name + " (segment " + std::to_string(p.spec.index) + ", frames " +
                       std::to_string(p.range.first) + ".." + std::to_string(p.range.end - 1) +
                       ") overlaps the part before it (a segment given twice?)");
    next = p.range.end;
  }
  if (next != a.runFrames)
    return makeError("frames " + std::to_string(next) + ".." + std::to_string(a.runFrames - 1) +
                     " are missing (the run has " + std::to_string(a.runFrames) +
                     " frames; give all " + std::to_string(a.spec.count) + " segments)");
  return order;
}

}  // namespace hlod
