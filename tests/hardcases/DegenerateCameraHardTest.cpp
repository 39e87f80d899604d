// Cameras at the singular places of the selection maths: inside a node's box, exactly on the
// plane between two children, at a node's centre (distance 0), looking straight down with the
// up vector parallel to the view, with no up vector, with the target on the eye. Asserts that
// every selector (hlod::makeSelector: lakhia, sse, fs, full) keeps every Selection field, load
// priority and hysteresis counter finite and its front sane; that the camera's basis, frustum
// planes and pixelsPerUnit stay finite; and that renderer::makeFrameView, the view the image is
// drawn with, is the camera the selectors culled for (the same forward, right and up), so that
// nothing the image shows was culled.
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../unit/RuntimeTestScene.h"
#include "hlod/runtime/LakhiaSelector.h"
#include "hlod/runtime/Selector.h"
#include "renderer/FrameView.h"

namespace {

using hlod::Camera;
using hlod::Skeleton;

bool finite(double v) {
  return std::isfinite(v);
}
bool finite(const glm::dvec3& v) {
  return finite(v.x) && finite(v.y) && finite(v.z);
}
bool finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!finite(m[c][r])) return false;
  return true;
}

struct NamedCamera {
  std::string name;
  Camera camera;
};

// The synthetic city's first block: hlod_0 box [0,40]^2 x [0,20], cut in thirds along x.
std::vector<NamedCamera> degenerateCameras(const Skeleton& sk) {
  const hlod::NodeInfo& root = sk.nodes[sk.roots[0]];
  const hlod::NodeInfo& child = sk.nodes[root.firstChild];
  const glm::dvec3 centre = child.centre;
  const double cut = child.bounds.max.x;  // the plane between the first two children
  auto cam = [](glm::dvec3 p, glm::dvec3 t, glm::dvec3 up = {0, 0, 1}) {
    Camera c;
    c.position = p;
    c.target = t;
    c.up = up;
    c.aspect = 16.0 / 9.0;
    return c;
  };
  return {
      {"inside a node box", cam(centre + glm::dvec3(1.0, 2.0, 3.0), {100, 100, 5})},
      {"on a cutting plane, looking along it", cam({cut, 10, 5}, {cut, 30, 5})},
      {"on a cutting plane, looking across it", cam({cut, 10, 5}, {cut + 10, 10, 5})},
      {"at a node centre (distance 0)", cam(centre, centre + glm::dvec3(0, 1, 0))},
      {"at a node centre, target on the eye", cam(centre, centre)},
      {"straight down, up parallel to the view", cam({100, 100, 150}, {100, 100, 0})},
      {"straight up, up parallel to the view", cam({20, 20, 1}, {20, 20, 50})},
      {"straight down at a node centre", cam(centre, centre - glm::dvec3(0, 0, 1))},
      {"no up vector", cam({-20, -20, 30}, {50, 50, 0}, {0, 0, 0})},
      {"on a box corner", cam(root.bounds.min, root.bounds.max)},
  };
}

// Forward, right and true up of a camera, as the image is drawn: the rows of makeFrameView's
// rotation are right, up and -forward.
struct Basis {
  glm::dvec3 forward, right, up;
};
Basis rendererBasis(const Camera& c) {
  const renderer::FrameView v = renderer::makeFrameView(c.position, c.target, c.up, c.fovY,
                                                        c.aspect, c.nearPlane, c.farPlane);
  const glm::dmat4& r = v.rotation;
  return {v.viewDir, {r[0][0], r[1][0], r[2][0]}, {r[0][1], r[1][1], r[2][1]}};
}

class DegenerateCamera : public ::testing::Test {
 protected:
  Skeleton sk = hlod::test::makeSyntheticCity({});
};

TEST_F(DegenerateCamera, TheCamerasBasisFrustumAndScaleStayFinite) {
  for (const auto& [name, c] : degenerateCameras(sk)) {
    SCOPED_TRACE(name);
    const glm::dvec3 f = c.forward(), r = c.right(), u = c.trueUp();
    ASSERT_TRUE(finite(f) && finite(r) && finite(u));
    EXPECT_NEAR(glm::length(f), 1.0, 1e-12);
    EXPECT_NEAR(glm::length(r), 1.0, 1e-12);
    EXPECT_NEAR(glm::length(u), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(f, r), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(f, u), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(r, u), 0.0, 1e-12);
    for (const hlod::Plane& p : c.frustum().planes) {
      EXPECT_TRUE(finite(p.normal) && finite(p.d));
      EXPECT_NEAR(glm::length(p.normal), 1.0, 1e-12);
    }
    for (double d : {0.0, 1e-300, 1.0, 1e300}) {
      const double ppu = c.pixelsPerUnit(d, 720.0);
      EXPECT_TRUE(finite(ppu) && ppu > 0.0) << d;
    }
  }
}

TEST_F(DegenerateCamera, TheRenderersViewMatricesStayFiniteAndOrthonormal) {
  for (const auto& [name, c] : degenerateCameras(sk)) {
    SCOPED_TRACE(name);
    const renderer::FrameView v = renderer::makeFrameView(c.position, c.target, c.up, c.fovY,
                                                          c.aspect, c.nearPlane, c.farPlane);
    ASSERT_TRUE(finite(v.rotation) && finite(v.projection) && finite(v.viewDir));
    const glm::dmat4 identity = v.rotation * glm::transpose(v.rotation);
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(identity[i][k], i == k ? 1.0 : 0.0, 1e-12);
  }
}

TEST_F(DegenerateCamera, TheImageIsDrawnFromTheCameraTheSelectorsCulledFor) {
  // Looking straight down with up = +Z, the camera's right was cross(f, x) and the renderer's
  // cross(f, y): the selectors' frustum was turned by 90 degrees against the 16:9 image, so the
  // nodes at the image's left and right edges were culled. With the target on the eye the
  // camera looked along +Y and the renderer along -Z.
  for (const auto& [name, c] : degenerateCameras(sk)) {
    SCOPED_TRACE(name);
    const Basis b = rendererBasis(c);
    EXPECT_LT(glm::length(b.forward - c.forward()), 1e-12);
    EXPECT_LT(glm::length(b.right - c.right()), 1e-12);
    EXPECT_LT(glm::length(b.up - c.trueUp()), 1e-12);
  }
}

TEST_F(DegenerateCamera, EveryNodeTheTopViewShowsIsInTheSelectorsFront) {
  // Straight down over a city of small blocks (6 m, 8 m streets, 1 m tall), 16:9: every hlod_0
  // box whose centre the image shows (inside the renderer's clip volume) must be drawn, at its
  // own level or finer. The image is 60 m wide and 33 m tall here; the frustum turned by 90
  // degrees culled the outer columns of blocks (centres 21 m left and right of the eye).
  hlod::test::SyntheticCity small;
  small.blockSize = 6.0;
  small.street = 8.0;
  small.height = 1.0;
  small.depth = 1;
  sk = hlod::test::makeSyntheticCity(small);
  Camera c;
  c.position = {24, 24, 30};
  c.target = {24, 24, 0};
  c.up = {0, 0, 1};
  c.aspect = 16.0 / 9.0;
  const renderer::FrameView v = renderer::makeFrameView(c.position, c.target, c.up, c.fovY,
                                                        c.aspect, c.nearPlane, c.farPlane);
  hlod::View view;
  view.camera = c;
  auto selector = hlod::makeSelector("full", sk);
  ASSERT_TRUE(selector.ok());
  const hlod::Selection s = (*selector)->select(view, hlod::AllResident{});
  std::set<std::uint32_t> drawnBlocks;
  for (std::uint32_t n : s.front) drawnBlocks.insert(sk.nodes[n].block);
  int shown = 0;
  for (std::uint32_t r : sk.roots) {
    const glm::dvec4 clip =
        v.projection * v.rotation * glm::dvec4(sk.nodes[r].bounds.centre() - c.position, 1.0);
    if (clip.w <= 0.0 || std::abs(clip.x) > clip.w || std::abs(clip.y) > clip.w) continue;
    ++shown;
    EXPECT_TRUE(drawnBlocks.count(sk.nodes[r].block)) << "block " << sk.nodes[r].block;
  }
  EXPECT_EQ(shown, 8);  // two rows of four
}

// A sane front: valid nodes, no duplicates, no node drawn with one of its ancestors, each
// resident.
void expectSaneFront(const Skeleton& sk, const hlod::Selection& s, const hlod::Residency& res) {
  std::set<std::uint32_t> front(s.front.begin(), s.front.end());
  EXPECT_EQ(front.size(), s.front.size()) << "a node drawn twice";
  for (std::uint32_t n : s.front) {
    ASSERT_LT(n, sk.nodes.size());
    EXPECT_TRUE(res.isResident(n));
    for (std::uint32_t p = sk.nodes[n].parent; p != hlod::kNoNode; p = sk.nodes[p].parent)
      EXPECT_FALSE(front.count(p)) << "node " << n << " drawn with its ancestor " << p;
  }
}

void expectFiniteSelection(const hlod::Selection& s) {
  EXPECT_TRUE(finite(s.estimatedMs));
  EXPECT_TRUE(finite(s.estimatedCost));
  EXPECT_TRUE(finite(s.targetMs));
  EXPECT_TRUE(finite(s.spentMs));
  EXPECT_TRUE(finite(s.drawBudgetMs));
  EXPECT_TRUE(finite(s.vTime) && s.vTime > 0.0);
  for (const hlod::LoadRequest& r : s.loadPriorities)
    ASSERT_TRUE(finite(r.priority) && r.priority >= 0.0) << "node " << r.node << ": " << r.priority;
}

TEST_F(DegenerateCamera, EverySelectorStaysFiniteWithASaneFront) {
  hlod::SelectorParams defaults;
  hlod::SelectorParams zeroFloors;  // the smallest values setSelectorParam accepts
  zeroFloors.lakhia.c_minDistance = 0.0;
  zeroFloors.lakhia.c_minCost = 0.0;
  zeroFloors.lakhia.c_velocity = 0.0;
  hlod::ResidencySet rootsOnly(sk.nodes.size());
  for (std::uint32_t r : sk.roots) rootsOnly.set(r, true);
  const hlod::AllResident all;
  for (const hlod::SelectorParams& params : {defaults, zeroFloors}) {
    for (const char* name : {"lakhia", "sse", "fs", "full"}) {
      for (const auto& [cameraName, c] : degenerateCameras(sk)) {
        SCOPED_TRACE(std::string(name) + ", " + cameraName +
                     (params.lakhia.c_minDistance == 0.0 ? ", zero floors" : ""));
        for (const hlod::Residency* res : {static_cast<const hlod::Residency*>(&all),
                                           static_cast<const hlod::Residency*>(&rootsOnly)}) {
          auto selector = hlod::makeSelector(name, sk, params);
          ASSERT_TRUE(selector.ok());
          hlod::View view;
          view.camera = c;
          view.velocity = c.forward() * 3.0;
          // Frames with feedback: the hysteresis and v_time loops run on these values too.
          for (int frame = 0; frame < 6; ++frame) {
            const hlod::Selection s = (*selector)->select(view, *res);
            expectFiniteSelection(s);
            expectSaneFront(sk, s, *res);
            if (const auto* lakhia = dynamic_cast<const hlod::LakhiaSelector*>(selector->get())) {
              const double limit = params.lakhia.c_hystLimit;
              for (std::uint32_t n = 0; n < sk.nodes.size(); ++n) {
                ASSERT_TRUE(finite(lakhia->hyst(n)) && std::abs(lakhia->hyst(n)) <= limit);
                ASSERT_TRUE(finite(lakhia->timeSlice(n)) && finite(lakhia->priority(n)));
              }
            }
            (*selector)->feedback(s.estimatedMs > 0.0 ? s.estimatedMs * 1.3 : 5.0);
          }
        }
      }
    }
  }
}

}  // namespace
