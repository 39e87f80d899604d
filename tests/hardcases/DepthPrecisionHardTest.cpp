// Depth precision at city scale: near plane 0.1 m, far plane 100 km, two parallel facades 1 cm
// apart 5 km from the camera, the front one red, the back one (1 m smaller on every side, so it
// lies wholly behind the front one) blue. Asserts that the front facade covers the back one in
// every pixel: no blue pixel, whatever the draw order, seen face-on, obliquely and at a grazing
// angle, at the origin and 6,400 km from it. A 24-bit depth buffer with the usual depth mapping
// resolves about 15 m at 5 km with these planes; reversed-Z with a float depth buffer, a few
// tenths of a millimetre.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "Places.h"
#include "hlod/geodesy/Geodesy.h"
#include "renderer/FrameView.h"
#include "renderer/GpuMesh.h"
#include "renderer/Renderer.h"

namespace {

constexpr double kNear = 0.1, kFar = 100000.0;
constexpr double kGap = 0.01;  // metres between the facades

using hardcase::Place;

// A facade in the plane y = y0 (facing -y), x in [x0, x1], z in [z0, z1], two triangles.
hlod::Mesh facade(const Place& place, double y0, double x0, double x1, double z0, double z1,
                  glm::vec4 colour) {
  hlod::Mesh m;
  m.baseColor = colour;
  for (const glm::dvec3& p : {glm::dvec3(x0, y0, z0), glm::dvec3(x1, y0, z0),
                              glm::dvec3(x1, y0, z1), glm::dvec3(x0, y0, z1)}) {
    m.positions.push_back(place.point(p));
    m.normals.emplace_back(place.direction({0, -1, 0}));
  }
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

struct Viewpoint {
  std::string name;
  glm::dvec3 eye, target;  // local coordinates
  double fovY;
};

TEST(DepthPrecision, AFacadeOneCentimetreInFrontOfAnotherAtFiveKilometresCoversItEverywhere) {
  auto ctx = renderer::createContext(renderer::Backend::Auto);
  ASSERT_TRUE(ctx.ok()) << ctx.message();
  renderer::RenderOptions options;
  options.width = 192;
  options.height = 96;
  options.effects.shading = hlod::Shading::Unlit;
  auto r = renderer::Renderer::create(**ctx, options);
  ASSERT_TRUE(r.ok()) << r.message();
  const std::vector<Place> places = hardcase::places();
  // Facades 2 km wide and 200 m tall at y = 5000; each view sees nothing but the front one.
  const std::vector<Viewpoint> views = {
      {"face-on", {0, 0, 100}, {0, 5000, 100}, 1.0},
      {"oblique (37 degrees)", {-3000, 1000, 100}, {0, 5000, 100}, 1.0},
      {"grazing (80 degrees)", {-4924, 4132, 100}, {0, 5000, 100}, 0.5},
  };
  for (const Place& place : places) {
    const hlod::Mesh front = facade(place, 5000.0, -1000, 1000, 0, 200, {1, 0, 0, 1});
    const hlod::Mesh back =
        facade(place, 5000.0 + kGap, -999, 999, 1, 199, {0, 0, 1, 1});  // 1 m inside
    auto gFront = renderer::GpuMesh::upload((*ctx)->gl(), hlod::toLocal(front));
    auto gBack = renderer::GpuMesh::upload((*ctx)->gl(), hlod::toLocal(back));
    ASSERT_TRUE(gFront.ok() && gBack.ok());
    for (const Viewpoint& v : views) {
      ASSERT_NEAR(glm::length(v.target - v.eye), 5000.0, 2.0);  // 5 km to the facade's middle
      for (bool frontFirst : {true, false}) {
        SCOPED_TRACE(place.name + ", " + v.name + (frontFirst ? ", front first" : ", back first"));
        const renderer::GpuMesh* list[2] = {&*gFront, &*gBack};
        if (!frontFirst) std::swap(list[0], list[1]);
        const auto view =
            renderer::makeFrameView(place.point(v.eye), place.point(v.target),
                                    place.direction({0, 0, 1}), v.fovY, 192.0 / 96.0, kNear, kFar);
        (*r)->drawFrame(view, list);
        const hlod::Image img = (*r)->readback();
        int red = 0, blue = 0;
        for (std::size_t i = 0; i < img.pixels.size(); i += 4) {
          red += img.pixels[i] > 200 && img.pixels[i + 2] < 60;
          blue += img.pixels[i + 2] > 200 && img.pixels[i] < 60;
        }
        EXPECT_EQ(blue, 0) << "z-fighting: the back facade shows through";
        EXPECT_EQ(red, img.width * img.height);
      }
    }
  }
}

}  // namespace
