// Fuzzes rendering of hostile geometry: raw float positions and normals (NaN, Inf, 1e38,
// subnormals), indices that may be out of range, a fuzzed camera and options (ray-cast shadows,
// shadow maps and shadow volumes included; with an odd vertex count the mesh is drawn twice, once
// blended, in back-to-front order). Invalid input must
// be refused before a byte is written; valid input must render without touching guard bytes.
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace facet;
  fuzz::Bytes in(data, size);
  const int w = 1 + in.take<std::uint8_t>() % 48, h = 1 + in.take<std::uint8_t>() % 48;
  const std::uint8_t flags = in.take<std::uint8_t>();
  const int vertex_count = in.take<std::uint8_t>() % 24;
  Scene s;
  s.camera.eye = Vec3(in.take<float>(), in.take<float>(), in.take<float>());
  s.camera.target = Vec3(in.take<float>(), in.take<float>(), in.take<float>());
  s.camera.vertical_fov_deg = 10.0f + float(in.take<std::uint8_t>() % 160);
  Mesh m;
  for (int i = 0; i < vertex_count; ++i) {
    m.positions.emplace_back(in.take<float>(), in.take<float>(), in.take<float>());
    m.normals.emplace_back(in.take<float>(), in.take<float>(), in.take<float>());
  }
  while (in.left() >= 3) {
    // Indices up to vertex_count + 2: some are out of range on purpose.
    std::array<std::uint32_t, 3> t;
    for (auto& i : t) i = in.take<std::uint8_t>() % static_cast<std::uint32_t>(vertex_count + 3);
    m.triangles.push_back(t);
  }
  s.meshes.push_back({"fuzz", m});
  s.materials.push_back(Material{});
  s.objects.push_back({0, 0, Mat4::Identity()});
  if (vertex_count & 1) {  // the mesh again, blended and moved, the blended objects sorted back to front
    Material glass;
    glass.blend = BlendMode::alpha;
    glass.alpha = 0.5f;
    s.materials.push_back(glass);
    Mat4 moved = Mat4::Identity();
    moved.block<3, 1>(0, 3) = Vec3(0.5f, 0.0f, -0.5f);
    s.objects.push_back({0, 1, moved});
    s.transparent_order = TransparentOrder::back_to_front;
  }
  Light light;
  light.type = LightType::point;
  light.position = s.camera.eye;
  s.lights.push_back(light);
  s.lights.push_back(Light{});

  const PixelFormat format = static_cast<PixelFormat>(flags % 3);
  fuzz::GuardedImage image(w, h, format, flags & 8 ? 5 : 0, (flags & 16) != 0);
  std::vector<float> depth_pixels(static_cast<std::size_t>(w * h) + 32, -7.0f);
  const DepthView depth{depth_pixels.data() + 16, w, h, static_cast<std::size_t>(w) * sizeof(float), false};
  RenderOptions options;
  options.threads = 1;
  options.shading = static_cast<ShadingMode>((flags >> 5) % 3);
  if (((flags >> 5) & 3) == 3) {  // Phong with shadows of both lights (ray-cast, 64^2 maps or volumes): the fuzzed mesh casts them
    options.shading = ShadingMode::phong;
    for (Light& l : s.lights) {
      l.shadow.method = (flags & 1) ? ShadowMethod::map : (flags & 2) ? ShadowMethod::volume : ShadowMethod::raycast;
      l.shadow.resolution = 64;
    }
  }
  options.cull = (flags & 4) ? CullMode::none : CullMode::back;
  options.path = (flags & 128) ? LightingPath::scalar : LightingPath::simd;
  static constexpr int kSamples[4] = {1, 1, 4, 16};  // multisampled for half the inputs
  options.samples = kSamples[size % 4];
  Renderer renderer;
  const Status st = renderer.render(s, options, image.view(), &depth, nullptr);
  image.check();
  for (int i = 0; i < 16; ++i)
    if (depth_pixels[static_cast<std::size_t>(i)] != -7.0f || depth_pixels[depth_pixels.size() - 1 - static_cast<std::size_t>(i)] != -7.0f) {
      fuzz::broken("write outside the depth buffer");
    }
  if (!st.ok() && st.message().empty()) fuzz::broken("an error without a message");
  return 0;
}
