// The frame plan's passes (frame/frame_plan.hpp), planned and checked without drawing a pixel:
// which passes a frame of each kind of shadow, reflection and sampling runs, in which order, with
// which targets and after-steps; and a blended double-sided draw's two draws (plan_units).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "frame/frame_plan.hpp"
#include "shadow_scenes.hpp"

namespace facet {
namespace {

using frame::AfterPass;
using frame::PassKind;

struct Planned {
  frame::FrameTargets targets;
  frame::FramePlan plan;
  std::vector<std::uint8_t> pixels;
  ImageView color;
};

// Plans a frame of `scene` into a 96 x 96 image; the plan points into `out`'s targets.
void plan(const Scene& scene, const RenderOptions& options, Planned& out, const frame::FrameKind& kind = {}) {
  out.pixels.assign(std::size_t{kSize} * kSize * 4, 0);
  out.color = {out.pixels.data(), kSize, kSize, std::size_t{kSize} * 4, PixelFormat::rgba8, false};
  frame::plan_frame(scene, options, kind, out.color, nullptr, nullptr, out.targets, out.plan);
}

std::vector<PassKind> kinds(const frame::FramePlan& p) {
  std::vector<PassKind> k;
  for (const frame::PlannedPass& pass : p.passes) k.push_back(pass.kind);
  return k;
}

TEST(FramePasses, AnUnshadowedSceneIsTheCameraPassAlone) {
  Scene s = sphere_over_plane();
  s.lights[0].shadow.method = ShadowMethod::none;
  Planned p;
  plan(s, RenderOptions{}, p);
  EXPECT_EQ(kinds(p.plan), std::vector<PassKind>{PassKind::camera});
  EXPECT_FALSE(p.plan.raycast);
  EXPECT_FALSE(p.plan.volumes);
  EXPECT_FALSE(p.plan.any_map());
  const frame::PlannedPass& c = p.plan.camera();
  EXPECT_EQ(c.after, AfterPass::nothing);
  EXPECT_EQ(c.pass.color, &p.color);
  EXPECT_FALSE(c.pass.depth_only);
  EXPECT_EQ(c.pass.width(), kSize);
  EXPECT_EQ(c.pass.samples.count, 1);
  EXPECT_EQ(p.plan.describe(), "camera: 96x96, gouraud, 1 sample\n");
}

TEST(FramePasses, RayCastShadowsBuildTheCastersBeforeTheCameraPass) {
  Planned p;
  plan(sphere_over_plane(), RenderOptions{}, p);
  EXPECT_EQ(kinds(p.plan), std::vector<PassKind>{PassKind::camera});
  EXPECT_TRUE(p.plan.raycast);
  EXPECT_NE(p.plan.describe().find("before the passes: build the ray-cast casters"), std::string::npos);
  // A part of a flat or Gouraud frame with shadows is drawn without them.
  frame::FrameKind part;
  part.kind = frame::FrameKind::Kind::part;
  plan(sphere_over_plane(), RenderOptions{}, p, part);
  EXPECT_FALSE(p.plan.raycast);
}

TEST(FramePasses, ShadowMapsDrawOneDepthPassPerFaceFirst) {
  // A directional light's map has one face; a point light's a cube of six.
  Scene s = with_map(sphere_over_plane(), ShadowFilter::pcf3x3, 512);
  Light point = s.lights[0];
  point.type = LightType::point;
  point.position = Vec3(3, 6, 0);
  s.lights.push_back(point);
  Planned p;
  plan(s, RenderOptions{}, p);
  ASSERT_EQ(p.plan.passes.size(), 8u) << p.plan.describe();
  for (int k = 0; k < 7; ++k) {
    const frame::PlannedPass& m = p.plan.passes[static_cast<std::size_t>(k)];
    EXPECT_EQ(m.kind, PassKind::shadow_map_face) << k;
    EXPECT_EQ(m.light, k == 0 ? 0u : 1u) << k;
    EXPECT_EQ(m.face, k == 0 ? 0 : k - 1) << k;
    EXPECT_TRUE(m.pass.depth_only && m.pass.casters_only) << k;
    EXPECT_EQ(m.pass.width(), 512) << k;
    EXPECT_EQ(m.pass.color, nullptr) << k;
    ASSERT_NE(m.pass.depth, nullptr) << k;
    EXPECT_EQ(m.pass.depth->width, 512) << k;
  }
  EXPECT_EQ(p.plan.camera().kind, PassKind::camera);
  ASSERT_EQ(p.plan.maps.size(), 2u);
  EXPECT_EQ(p.plan.maps[0], &p.targets.maps[0]);
  EXPECT_EQ(p.plan.maps[1], &p.targets.maps[1]);
  EXPECT_EQ(p.plan.shadow_map_texels, 7u * 512 * 512);
  EXPECT_NE(p.plan.describe().find("shadow map face: 512x512, depth only, light 1, face 5\n"), std::string::npos)
      << p.plan.describe();
}

TEST(FramePasses, AMapWithNothingToCastHasNoPass) {
  Scene s = with_map(sphere_over_plane(), ShadowFilter::pcf3x3, 512);
  for (Instance& o : s.objects) o.cast_shadows = false;
  Planned p;
  plan(s, RenderOptions{}, p);
  EXPECT_EQ(kinds(p.plan), std::vector<PassKind>{PassKind::camera});
  EXPECT_FALSE(p.plan.any_map());
  EXPECT_EQ(p.plan.maps[0], nullptr);
}

TEST(FramePasses, ShadowVolumesDrawTheCamerasDepthThenBuildTheirMasks) {
  RenderOptions o;
  o.samples = 4;
  o.shading = ShadingMode::phong;
  Planned p;
  plan(with_volume(sphere_over_plane()), o, p);
  ASSERT_EQ(kinds(p.plan), (std::vector<PassKind>{PassKind::volume_depth, PassKind::camera})) << p.plan.describe();
  const frame::PlannedPass& d = p.plan.passes[0];
  EXPECT_TRUE(p.plan.volumes);
  EXPECT_EQ(d.after, AfterPass::build_shadow_volumes);
  EXPECT_TRUE(d.pass.depth_only);
  EXPECT_FALSE(d.pass.casters_only);  // every object that writes depth, as the camera's pass draws them
  EXPECT_EQ(d.pass.depth, &p.targets.volume_depth);
  EXPECT_EQ(d.pass.samples.count, 1);  // multisampling is the camera's colour pass alone
  EXPECT_EQ(d.pass.view, p.plan.camera().pass.view);
  EXPECT_EQ(p.plan.camera().pass.samples.count, 4);
  EXPECT_EQ(p.plan.describe(),
            "volume depth: 96x96, depth only, then build shadow volumes\ncamera: 96x96, phong, 4 samples\n");
}

// A ball whose material reflects the scene around it (a dynamic cube map), over the plane.
Scene dynamic_reflector() {
  Scene s = sphere_over_plane();
  s.lights[0].shadow.method = ShadowMethod::none;
  Material chrome;
  chrome.environment.mode = EnvironmentMode::cube;
  chrome.environment.dynamic = true;
  chrome.environment.resolution = 32;
  s.materials.push_back(chrome);
  s.objects[1].material = 1;
  return s;
}

TEST(FramePasses, DynamicReflectorsDrawSixFacesBeforeTheCamera) {
  Planned p;
  plan(dynamic_reflector(), RenderOptions{}, p);
  ASSERT_EQ(p.plan.passes.size(), 7u) << p.plan.describe();
  for (int f = 0; f < 6; ++f) {
    const frame::PlannedPass& e = p.plan.passes[static_cast<std::size_t>(f)];
    EXPECT_EQ(e.kind, PassKind::environment_face);
    EXPECT_EQ(e.after, AfterPass::finish_environment_face);
    EXPECT_EQ(e.object, 1u);
    EXPECT_EQ(e.pass.exclude_object, 1u);  // the ball is not in its own reflection
    EXPECT_EQ(e.face, f);
    EXPECT_EQ(e.cube, 0);
    EXPECT_EQ(e.pass.width(), 32);
    EXPECT_EQ(e.pass.color, &p.targets.cube_faces[0].views[static_cast<std::size_t>(f)]);
  }
  EXPECT_EQ(p.targets.cubes.of_object, (std::vector<std::int32_t>{-1, 0}));
  EXPECT_EQ(p.targets.cubes.samplers.size(), 6u);
  // A visibility sub-frame draws plain surfaces: no reflection, no face pass.
  frame::FrameKind visibility;
  visibility.kind = frame::FrameKind::Kind::visibility;
  plan(dynamic_reflector(), RenderOptions{}, p, visibility);
  EXPECT_EQ(kinds(p.plan), std::vector<PassKind>{PassKind::camera});
}

TEST(FramePasses, ADoubleSidedBlendedObjectIsTwoDrawsBackFacesFirst) {
  Scene s = sphere_over_plane();
  s.lights[0].shadow.method = ShadowMethod::none;
  Material glass;
  glass.alpha = 0.5f;
  glass.blend = BlendMode::alpha;
  s.materials.push_back(glass);
  s.objects[1].material = 1;
  s.objects[1].double_sided = true;
  s.transparent_order = TransparentOrder::back_to_front;  // as models are drawn (submission order: one draw)
  Planned p;
  plan(s, RenderOptions{}, p);
  std::vector<frame::DrawUnit> units;
  std::vector<scene_order::ObjectKey> keys;
  frame::plan_units(s, p.plan.camera().pass, units, keys, false);
  ASSERT_EQ(units.size(), 3u);
  EXPECT_EQ(units[0].object, 0u);  // the opaque plane first
  EXPECT_EQ(units[0].only, 0);
  EXPECT_EQ(units[1].object, 1u);  // then the ball's back faces, then its front faces
  EXPECT_EQ(units[1].only, 2);
  EXPECT_EQ(units[2].object, 1u);
  EXPECT_EQ(units[2].only, 1);
}

}  // namespace
}  // namespace facet
