// Fill-rate scenes shared by the frame benchmarks and the llvmpipe comparison: full-screen layers
// drawn back to front, so every layer passes the depth test.
#pragma once

#include <cstdint>
#include <vector>

#include "facet/facet.hpp"

namespace facet::bench {

enum class Layers { plain, textured, blended, textured_fog };

// `layers` quads covering a 90-degree view, from depth -50 towards the camera. plain: emissive
// (or, `lit`, one point light); textured: a 256x256 trilinear checker texture repeated
// across each layer 32 times (minified: about 4 texels a pixel, so trilinear blends levels 1 and
// 2; GL_MODULATE, separate specular), lit by a directional light; blended: alpha 0.5;
// textured_fog: textured, in linear fog (the layers' factors 0.3 to 0.6).
inline Scene layers_scene(int layers, bool lit = false, Layers kind = Layers::plain) {
  Scene s;
  s.camera.eye = Vec3(0, 0, 0);
  s.camera.target = Vec3(0, 0, -1);
  s.camera.vertical_fov_deg = 90;
  s.camera.far = 1000;
  Mesh quad;
  quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  quad.normals.assign(4, Vec3(0, 0, 1));
  quad.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.meshes.push_back({"quad", quad});
  Material m;
  m.emissive = Color3(0.3f, 0.5f, 0.7f);
  if (lit) {
    m.emissive = Color3(0.05f, 0.05f, 0.05f);
    m.specular = Color3(0.5f, 0.5f, 0.5f);
    m.shininess = 24;
    Light l;
    l.type = LightType::point;
    l.position = Vec3(0.0f, 0.0f, 0.0f);
    l.linear_attenuation = 0.01f;
    s.lights.push_back(l);
  }
  if (kind == Layers::textured || kind == Layers::textured_fog) {
    constexpr int kSide = 256;
    std::vector<std::uint8_t> texels(4 * kSide * kSide);
    for (int j = 0; j < kSide; ++j) {
      for (int i = 0; i < kSide; ++i) {
        const bool light = ((i / 16) + (j / 16)) % 2 == 1;
        std::uint8_t* t = &texels[static_cast<std::size_t>(4 * (j * kSide + i))];
        t[0] = light ? 230 : 60, t[1] = light ? 210 : 90, t[2] = light ? 170 : 140, t[3] = 255;
      }
    }
    s.textures.push_back(*make_texture("checker", kSide, kSide, texels));
    m.emissive = Color3(0.1f, 0.1f, 0.1f);
    m.diffuse = Color3(0.8f, 0.8f, 0.8f);
    m.specular = Color3(0.3f, 0.3f, 0.3f);
    m.shininess = 16;
    m.diffuse_texture = 0;
    m.uv_scale = Vec2(32.0f, 32.0f);
    Light sun;
    sun.direction = Vec3(0.2f, -0.3f, -1.0f);
    s.lights.push_back(sun);
    if (kind == Layers::textured_fog) {
      s.fog.mode = FogMode::linear;
      s.fog.color = Color3(0.6f, 0.65f, 0.7f);
      s.fog.start = 20.0f, s.fog.end = 70.0f;
    }
  } else if (kind == Layers::blended) {
    m.blend = BlendMode::alpha;
    m.alpha = 0.5f;
  }
  s.materials.push_back(m);
  for (int i = 0; i < layers; ++i) {
    const float z = -50.0f + float(i);
    Mat4 t = Mat4::Identity();
    t.topLeftCorner<3, 3>() *= -z * 2.0f;  // large enough to cover the view at that depth
    t(2, 3) = z;
    s.objects.push_back({0, 0, t});
  }
  return s;
}

}  // namespace facet::bench
