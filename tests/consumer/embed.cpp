// Embedding facet: a host renders a sphere into its own buffer. The README quotes this file.
#include <cstdio>
#include <vector>

#include <facet/facet.hpp>

int main() {
  facet::Scene scene;
  scene.meshes.push_back({"ball", facet::make_uv_sphere(1.0f, 48, 24)});
  facet::Material clay;
  clay.diffuse = facet::Color3(0.8f, 0.5f, 0.3f);
  clay.specular = facet::Color3(0.4f, 0.4f, 0.4f);
  clay.shininess = 32;
  scene.materials.push_back(clay);
  facet::Mat4 model = facet::Mat4::Identity();  // a transform: it must reach the library intact
  model(0, 3) = 0.25f;
  model(1, 1) = 1.5f;
  scene.objects.push_back({0, 0, model});
  scene.lights.push_back(facet::Light{});  // white, directional, along -z
  scene.camera.eye = facet::Vec3(0, 0, 4);

  std::vector<std::uint8_t> pixels(320 * 240 * 4);  // the host's buffer
  const facet::ImageView image{pixels.data(), 320, 240, 320 * 4, facet::PixelFormat::rgba8, false};
  facet::RenderOptions config;
  config.shading = facet::ShadingMode::phong;
  facet::Renderer renderer(config);
  if (facet::Status s = renderer.render(scene, image); !s.ok()) {
    std::fprintf(stderr, "render failed: %s\n", s.message().c_str());
    return 1;
  }
  std::printf("%llu pixels filled\n", static_cast<unsigned long long>(renderer.last_stats().pixels_filled));
  return renderer.last_stats().pixels_filled > 0 && pixels[4 * (120 * 320 + 160)] > 0 ? 0 : 1;
}
