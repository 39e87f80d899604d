// Occlusion culling, one frame late: Manocha sec. 2.3, 4.1-4.3, 5.1.2 and CHC++ (Mattausch et
// al. 2008). See hlod/runtime/OcclusionCulling.h for which rule comes from where.
#include "hlod/runtime/OcclusionCulling.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace hlod {

std::size_t OcclusionPlan::queries() const {
  return boxBatches.size() +
         static_cast<std::size_t>(std::count(queryDraw.begin(), queryDraw.end(), 1));
}

OcclusionCulling::OcclusionCulling(const Skeleton& skeleton, const OcclusionParams& params)
    : skeleton_(skeleton),
      params_(params),
      state_(skeleton.nodes.size()),
      reached_(skeleton.nodes.size(), 0),
      hiddenAt_(skeleton.nodes.size(), 0) {
  assert(params_.c_visibleFrames >= 1 && params_.c_trustFrames >= 1 && params_.c_maxBatch >= 1);
}

void OcclusionCulling::reset() {
  std::fill(state_.begin(), state_.end(), NodeState{});
}

bool OcclusionCulling::freshHidden(std::uint32_t node) const {
  // Asked while planning frame_: an answer to the previous plan.
  const NodeState& s = state_[node];
  return s.known == Known::Hidden && s.resultFrame + 1 == frame_;
}

bool OcclusionCulling::occluded(std::uint32_t node) const {
  assert(node < state_.size());
  const NodeState& s = state_[node];
  // Asked while frame_ + 1 is being selected: a result of the last plan is one frame old.
  if (s.known != Known::Hidden || frame_ + 1 - s.resultFrame > params_.c_trustFrames) return false;
  // An ancestor shown since: this answer was given while the subtree was hidden as a whole.
  for (std::uint32_t a = skeleton_.nodes[node].parent; a != kNoNode; a = skeleton_.nodes[a].parent)
    if (state_[a].shownAt > s.resultFrame) return false;
  return true;
}

std::uint32_t OcclusionCulling::jitter(std::uint32_t node) const {
  // A fixed hash, not a random generator: settled runs stay reproducible.
  std::uint32_t h = node * 0x9e3779b1u;
  h ^= h >> 16;
  return h % params_.c_visibleFrames;
}

double OcclusionCulling::keepProbability(std::uint32_t frames) {
  return 0.99 - 0.7 * std::exp(-static_cast<double>(frames));
}

std::vector<std::size_t> OcclusionCulling::batchSizes(std::span<const double> sortedKeep,
                                                      std::size_t maxBatch) {
  assert(maxBatch >= 1);
  std::vector<std::size_t> sizes;
  std::size_t i = 0;
  while (i < sortedKeep.size()) {
    // Grow the batch while its value |M| / (1 + (1 - prod p) |M|) grows.
    double keepAll = sortedKeep[i];
    double value = 1.0 / (1.0 + (1.0 - keepAll));
    std::size_t m = 1;
    while (i + m < sortedKeep.size() && m < maxBatch) {
      const double keep = keepAll * sortedKeep[i + m];
      const double next = double(m + 1) / (1.0 + (1.0 - keep) * double(m + 1));
      if (!(next > value)) break;
      keepAll = keep;
      value = next;
      ++m;
    }
    sizes.push_back(m);
    i += m;
  }
  return sizes;
}

void OcclusionCulling::receive(std::span<const OcclusionResult> results) {
  for (const OcclusionResult& r : results) {
    assert(!r.nodes.empty());
    const bool visible = r.samples > 0;
    if (!r.answered || (r.nodes.size() > 1 && visible)) {
      // Not answered, or a batch with a visible node in it (which one is not known): drawn next
      // frame, each with its draw queried.
      for (std::uint32_t n : r.nodes) {
        NodeState& s = state_[n];
        s.known = Known::Unknown;
        s.hiddenFrames = 0;
        s.shownAt = frame_;
      }
      continue;
    }
    for (std::uint32_t n : r.nodes) {
      assert(n < state_.size());
      NodeState& s = state_[n];
      if (visible) {
        // Re-tested after c_visibleFrames; a node that just became visible after a jittered
        // share of that, so that nodes uncovered together do not come due together.
        const bool wasVisible = s.known == Known::Visible;
        s.known = Known::Visible;
        s.hiddenFrames = 0;
        s.samples = r.samples;
        s.nextTest = frame_ + (wasVisible ? params_.c_visibleFrames : 1 + jitter(n));
        s.shownAt = frame_;
        if (s.pulledAt == frame_) s.noPullUntil = frame_ + params_.c_noPullFrames;
      } else {
        s.hiddenFrames = s.known == Known::Hidden ? s.hiddenFrames + 1 : 1;
        s.known = Known::Hidden;
        s.samples = 0;
      }
      s.resultFrame = frame_;
    }
  }
}

OcclusionPlan OcclusionCulling::plan(std::span<const std::uint32_t> front,
                                     std::span<const std::uint32_t> hidden) {
  ++frame_;
  assert(frame_ != 0 && "frame counter wrapped");
  const std::uint32_t f = frame_;
  counters_ = {};
  OcclusionPlan plan;

  // Occluders: drawn anyway. Queried with their own draw when unknown or due for a re-test.
  plan.queryDraw.resize(front.size(), 0);
  for (std::size_t i = 0; i < front.size(); ++i) {
    const NodeState& s = state_[front[i]];
    if (s.known != Known::Visible || s.nextTest <= f) plan.queryDraw[i] = 1;
  }

  // Pull-up: a node whose reached children are all hidden by the last frame's queries is
  // queried in their place (one query for the subtree; if it comes back hidden, the walk stops
  // at it). Reached: drawn, hidden, or above one of those.
  const auto& nodes = skeleton_.nodes;
  auto reach = [&](std::uint32_t n) {
    while (n != kNoNode && reached_[n] != f) {
      reached_[n] = f;
      n = nodes[n].parent;
    }
  };
  for (std::uint32_t n : front) reach(n);
  for (std::uint32_t n : hidden) {
    hiddenAt_[n] = f;
    reach(n);
  }
  std::vector<std::uint32_t> queried;
  queried.reserve(hidden.size());
  for (std::uint32_t n : hidden) {
    const std::uint32_t p = nodes[n].parent;
    bool pull = p != kNoNode && freshHidden(n) && state_[p].noPullUntil < f;
    if (pull) {
      for (std::uint32_t c = nodes[p].firstChild; c < nodes[p].firstChild + nodes[p].childCount;
           ++c)
        if (reached_[c] == f && !(hiddenAt_[c] == f && freshHidden(c))) pull = false;
    }
    if (!pull) {
      queried.push_back(n);
    } else if (hiddenAt_[p] != f) {
      hiddenAt_[p] = f;  // once, for all its children
      state_[p].pulledAt = f;
      queried.push_back(p);
      ++counters_.pulledUp;
    }
  }

  // Multiqueries: most likely to stay hidden first. A node not hidden before (a pulled-up one)
  // is queried alone: its answer is the one most likely to come back visible.
  std::stable_sort(queried.begin(), queried.end(), [&](std::uint32_t a, std::uint32_t b) {
    return state_[a].hiddenFrames > state_[b].hiddenFrames;
  });
  std::size_t firstNew = 0;
  std::vector<double> keep;
  for (; firstNew < queried.size(); ++firstNew) {
    const NodeState& s = state_[queried[firstNew]];
    if (s.known != Known::Hidden || s.hiddenFrames == 0) break;
    keep.push_back(keepProbability(s.hiddenFrames));
  }
  std::size_t at = 0;
  for (std::size_t size : batchSizes(keep, params_.c_maxBatch)) {
    plan.boxBatches.emplace_back(queried.begin() + at, queried.begin() + at + size);
    at += size;
  }
  for (; at < queried.size(); ++at) plan.boxBatches.push_back({queried[at]});

  counters_.boxQueries = static_cast<std::uint32_t>(plan.boxBatches.size());
  counters_.drawQueries =
      static_cast<std::uint32_t>(std::count(plan.queryDraw.begin(), plan.queryDraw.end(), 1));
  counters_.queries = counters_.boxQueries + counters_.drawQueries;
  counters_.queriedBoxes = static_cast<std::uint32_t>(queried.size());
  return plan;
}

}  // namespace hlod
