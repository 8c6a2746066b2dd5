// Mirrored instances: an object drawn with a negative-determinant model matrix must look exactly
// like its mirror image built into the mesh (positions mirrored, normals mirrored, winding
// reversed) under an ordinary matrix: the same coverage and depth (bit for bit: the clip positions
// are the same products), colours within 1 step (the normal matrix is another inverse), with
// culling on and off, one- and two-sided, in every shading mode, on every path and ISA.
#include <cmath>

#include "render_support.hpp"

namespace facet {
namespace {

Mat4 rotation_translation() {
  Mat4 m = Mat4::Identity();
  const Eigen::Matrix3f r = (Eigen::AngleAxisf(0.7f, Vec3(0.3f, 1.0f, 0.2f).normalized()) *
                             Eigen::AngleAxisf(-0.4f, Vec3(1.0f, 0.0f, 0.0f)))
                                .toRotationMatrix();
  m.topLeftCorner<3, 3>() = r;
  m(0, 3) = 0.3f;
  m(2, 3) = -4.0f;
  return m;
}

// The mirror x -> -x of `mesh`, as a mesh of its own: a proper (front faces outside) mesh again.
Mesh mirrored_copy(const Mesh& mesh) {
  Mesh m = mesh;
  for (Vec3& p : m.positions) p.x() = -p.x();
  for (Vec3& n : m.normals) n.x() = -n.x();
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

Scene base_scene(bool two_sided) {
  Scene s = test::camera_scene();
  s.camera.vertical_fov_deg = 40;
  s.two_sided = two_sided;
  s.global_ambient = Color3(0.1f, 0.1f, 0.1f);
  Material m;
  m.diffuse = Color3(0.8f, 0.5f, 0.3f);
  m.specular = Color3(0.6f, 0.6f, 0.6f);
  m.shininess = 24;
  s.materials.push_back(m);
  Light key;
  key.type = LightType::point;
  key.position = Vec3(-2.0f, 2.5f, 1.0f);
  s.lights.push_back(key);
  Light fill;
  fill.direction = Vec3(0.5f, -0.2f, -1.0f);
  fill.diffuse = Color3(0.3f, 0.3f, 0.4f);
  s.lights.push_back(fill);
  return s;
}

struct Frame {
  std::vector<std::uint8_t> pixels;
  std::vector<float> depth;
  FrameStats stats;
};

Frame render(const Scene& scene, const RenderOptions& o) {
  constexpr int kW = 160, kH = 120;
  test::Canvas c(kW, kH);
  Frame f;
  f.depth.assign(kW * kH, -1.0f);
  const DepthView d{f.depth.data(), kW, kH, kW * sizeof(float), false};
  Renderer r;
  EXPECT_TRUE(r.render(scene, o, c.view(), &d, &f.stats).ok());
  f.pixels = c.pixels();
  return f;
}

TEST(RenderMirror, MirroredInstanceLooksLikeItsMirroredMesh) {
  // A torus cut open (half its triangles) so that culling and two-sided lighting both matter.
  Mesh torus = make_torus(0.9f, 0.35f, 40, 20);
  torus.triangles.resize(torus.triangles.size() / 2);
  Mat4 mirror = Mat4::Identity();
  mirror(0, 0) = -1.0f;
  std::vector<Isa> isas{Isa::sse2};
  for (Isa isa : {Isa::avx2, Isa::avx512})
    if (isa_supported(isa)) isas.push_back(isa);
  for (bool two_sided : {false, true}) {
    Scene mirrored = base_scene(two_sided), built = base_scene(two_sided);
    mirrored.meshes.push_back({"torus", torus});
    mirrored.objects.push_back({0, 0, rotation_translation() * mirror});
    built.meshes.push_back({"torus", mirrored_copy(torus)});
    built.objects.push_back({0, 0, rotation_translation()});
    for (ShadingMode mode : {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong}) {
      for (CullMode cull : {CullMode::back, CullMode::none, CullMode::front}) {
        for (LightingPath path : {LightingPath::scalar, LightingPath::simd}) {
          for (Isa isa : isas) {
            if (path == LightingPath::scalar && isa != Isa::sse2) continue;
            RenderOptions o;
            o.shading = mode;
            o.cull = cull;
            o.path = path;
            o.isa = isa;
            const Frame a = render(mirrored, o), b = render(built, o);
            const std::string what = std::string(to_string(mode)) + ", cull " + std::to_string(int(cull)) + ", " +
                                     to_string(path) + " " + to_string(isa) + (two_sided ? ", two-sided" : "");
            EXPECT_EQ(a.stats.triangles_culled, b.stats.triangles_culled) << what;
            EXPECT_GT(a.stats.pixels_filled, 500u) << what;
            EXPECT_TRUE(a.depth == b.depth) << what;
            int worst = 0;
            for (std::size_t i = 0; i < a.pixels.size(); ++i) worst = std::max(worst, std::abs(int(a.pixels[i]) - int(b.pixels[i])));
            EXPECT_LE(worst, 1) << what;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace facet
