// The scene drawn by OpenGL 2.1's fixed function (facet_vs_llvmpipe.cpp says how each facet
// feature maps onto GL's): what GL cannot draw, the GL objects a scene needs, and the draw.
#include "gl_scene.hpp"

#include <GL/glext.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace gl_compare {

bool has_surfaces(const facet::Scene& s) {
  if (!s.textures.empty() || s.fog.mode != facet::FogMode::none) return true;  // includes emissive and environment maps
  for (const auto& m : s.materials)
    if (m.blend != facet::BlendMode::opaque || m.alpha_cutoff > 0 || m.alpha_to_coverage ||
        m.diffuse_texture != facet::kNoTexture)
      return true;
  for (const auto& m : s.meshes)
    if (!m.mesh.colors.empty()) return true;
  return false;
}

// Lights for the comparison: a directional key light, then point and GL spot lights around.
std::vector<facet::Light> light_set(int count, const facet::Vec3& centre, float radius) {
  std::vector<facet::Light> v;
  for (int i = 0; i < count; ++i) {
    facet::Light l;
    const float a = 2.0f * 3.14159265f * float(i) / float(std::max(count, 1));
    const facet::Vec3 p = centre + radius * facet::Vec3(2.0f * std::cos(a), 1.5f, 2.0f * std::sin(a) + 1.0f);
    const float k = 0.9f / float(count);  // keep the sum of lights from saturating everything
    l.diffuse = facet::Color3(k, k * 0.95f, k * 0.9f) * 1.6f;
    l.specular = facet::Color3(0.5f, 0.5f, 0.5f);
    l.ambient = facet::Color3(0.02f, 0.02f, 0.02f);
    switch (i % 3) {
      case 0: l.type = facet::LightType::directional; l.direction = (centre - p).normalized(); break;
      case 1:
        l.type = facet::LightType::point;
        l.position = p;
        l.linear_attenuation = 0.05f / radius;
        break;
      default:
        l.type = facet::LightType::spot;
        l.position = p;
        l.direction = centre - p;
        l.spot_cutoff_deg = 35;
        l.spot_exponent = 4;
        break;
    }
    v.push_back(l);
  }
  return v;
}

// The scene's bounding sphere (world space), to place lights.
void bounds(const facet::Scene& s, facet::Vec3& centre, float& radius) {
  facet::Vec3 lo = facet::Vec3::Constant(1e30f), hi = facet::Vec3::Constant(-1e30f);
  for (const auto& o : s.objects) {
    for (const auto& p : s.meshes[o.mesh].mesh.positions) {
      const facet::Vec3 w = (o.model * p.homogeneous()).head<3>();
      lo = lo.cwiseMin(w), hi = hi.cwiseMax(w);
    }
  }
  centre = 0.5f * (lo + hi);
  radius = std::max(0.5f * (hi - lo).norm(), 1e-3f);
}

namespace {

// The one enabled light, or nullptr.
const facet::Light* only_light(const facet::Scene& s) {
  const facet::Light* one = nullptr;
  for (const facet::Light& l : s.lights) {
    if (!l.enabled) continue;
    if (one) return nullptr;
    one = &l;
  }
  return one;
}

bool has_projector(const facet::Scene& s) {
  for (const facet::Light& l : s.lights)
    if (l.enabled && l.type == facet::LightType::spot && l.projector.texture != facet::kNoTexture) return true;
  return false;
}

// Projectors and normal maps, which facet lights per pixel, have GL 2.1 equivalents only in a
// narrow scene. A projector is a texture unit under GL_MODULATE with eye-linear texgen and the
// light's matrix: it multiplies the whole fragment, facet one light's diffuse and specular, so the
// projector must be the only light, with no ambient light and no emission or other textures. A
// normal map is ARB_texture_env_dot3: the texel dotted with the light vector in tangent space (the
// vertex colour), times the diffuse colour, so one directional light, diffuse only, no ambient,
// emission or other maps, and normal_scale 1. Both need --shading phong (facet applies them per
// pixel only); GL lights per vertex, so the scenes are finely tessellated.
std::string per_pixel_incompatibility(const facet::Scene& s, bool phong) {
  bool normal_maps = false;
  for (const facet::Material& m : s.materials) normal_maps |= m.normal_texture != facet::kNoTexture;
  const bool projector = has_projector(s);
  if (!phong) return {};  // Gouraud: facet applies none of them, and GL draws none
  if (!projector && !normal_maps) {
    for (const facet::Material& m : s.materials)
      if (m.occlusion_texture != facet::kNoTexture || m.bump_texture != facet::kNoTexture) {
        return "occlusion and bump maps have no GL 2.1 equivalent here";
      }
    return {};
  }
  if (projector && normal_maps) return "a projector and a normal map in one scene";
  const facet::Light* light = only_light(s);
  if (!light) return "a projector or normal map needs the scene's only light (GL applies them to the whole fragment)";
  if (!light->ambient.isZero() || !s.global_ambient.isZero()) return "a projector or normal map needs no ambient light";
  if (normal_maps && light->type != facet::LightType::directional) return "DOT3 bump mapping needs a directional light";
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const facet::Material& m = s.materials[i];
    const std::string at = "materials[" + std::to_string(i) + "]: ";
    if (!m.emissive.isZero()) return at + "emission with a projector or normal map";
    if (m.diffuse_texture != facet::kNoTexture || m.emissive_texture != facet::kNoTexture ||
        m.occlusion_texture != facet::kNoTexture || m.bump_texture != facet::kNoTexture ||
        m.environment.mode != facet::EnvironmentMode::none) {
      return at + "another texture with a projector or normal map";
    }
    if (projector) {
      const facet::Texture& t = s.textures[static_cast<std::size_t>(light->projector.texture)];
      if (light->projector.mode == facet::ProjectorMode::gobo && t.encoding != facet::TextureEncoding::linear)
        return "an sRGB gobo picture (GL would take the luminance of encoded values)";
    }
    if (normal_maps && (m.normal_texture == facet::kNoTexture || !m.specular.isZero() || m.normal_scale != 1.0f))
      return at + "DOT3 bump mapping needs every material normal-mapped, no specular and normal_scale 1";
  }
  for (const auto& nm : s.meshes)
    if (!nm.mesh.colors.empty()) return "vertex colours with a projector or normal map";
  return {};
}

}  // namespace

// Every reason the scene cannot be drawn by GL 2.1 here, joined with "; " (empty: none), so that a
// scene's author learns all of them from one run.
std::string gl_incompatibility(const facet::Scene& s, bool phong) {
  std::vector<std::string> why;
  for (std::size_t i = 0; i < s.lights.size(); ++i) {
    const facet::Light& l = s.lights[i];
    const std::string at = "lights[" + std::to_string(i) + "]: ";
    if (l.type == facet::LightType::spot && l.spot_shape != facet::SpotShape::cutoff_exponent) why.push_back(at + "smooth cones are not OpenGL 2.1");
    if (l.range > 0) why.push_back(at + "light ranges are not OpenGL 2.1");
    if (l.type != facet::LightType::directional && l.attenuation_model != facet::AttenuationModel::gl) {
      why.push_back(at + "linear range attenuation is not OpenGL 2.1");
    }
  }
  if (s.lights.size() > 8) why.push_back("more than 8 lights (GL_MAX_LIGHTS)");
  if (const std::string pp = per_pixel_incompatibility(s, phong); !pp.empty()) why.push_back(pp);
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const facet::Material& m = s.materials[i];
    const std::string at = "materials[" + std::to_string(i) + "]: ";
    if (m.shininess > 128) why.push_back(at + "shininess above 128 (GL's limit)");
    if (m.specular_model != facet::SpecularModel::blinn) why.push_back(at + "GL 2.1's lobe is Blinn's");
    if (m.emissive_texture != facet::kNoTexture &&
        s.textures[static_cast<std::size_t>(m.emissive_texture)].encoding != facet::TextureEncoding::linear) {
      why.push_back(at + "an sRGB emissive texture (this program premultiplies emissive textures as stored)");
    }
  }
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    if (s.objects[i].lightmap >= 0) why.push_back("objects[" + std::to_string(i) + "]: lightmaps are not drawn by this program");
  }
  std::string joined;
  for (const std::string& w : why) joined += (joined.empty() ? "" : "; ") + w;
  return joined;
}

namespace {

void gl_colour(GLenum light_or_face, GLenum what, const facet::Color3& c, float alpha, bool material) {
  const GLfloat v[4] = {c.x(), c.y(), c.z(), alpha};
  if (material) {
    glMaterialfv(light_or_face, what, v);
  } else {
    glLightfv(light_or_face, what, v);
  }
}

void gl_sampling(const facet::Texture& t) {
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, static_cast<GLint>(t.levels.size()) - 1);
  const bool nearest = t.filter == facet::TextureFilter::nearest;
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, nearest ? GL_NEAREST : GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                  nearest ? GL_NEAREST : t.filter == facet::TextureFilter::bilinear ? GL_LINEAR : GL_LINEAR_MIPMAP_LINEAR);
  const GLint wrap = t.wrap == facet::TextureWrap::repeat ? GL_REPEAT
                     : t.wrap == facet::TextureWrap::clamp ? GL_CLAMP_TO_EDGE
                                                           : GL_MIRRORED_REPEAT;
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
}

// --shading phong (per_pixel_incompatibility has let the scene through): the projector's picture,
// level 0 as facet reads it, clamped to a black border (facet: no light outside [0, 1]); a gobo
// as the picture's luminance. DOT3: per vertex, the light vector in the tangent frame facet maps
// normals with (t, w n x t, n; world space) as the colour 1/2 + l/2.
void gl_prepare_per_pixel(const facet::Scene& s, GlScene& g) {
  const facet::Light* light = only_light(s);
  if (light && has_projector(s)) {
    const facet::Texture& t = s.textures[static_cast<std::size_t>(light->projector.texture)];
    const facet::TextureLevel& l = t.levels[0];
    const auto* from = reinterpret_cast<const std::uint8_t*>(t.texels.data() + l.offset);
    const std::size_t n = static_cast<std::size_t>(l.width) * static_cast<std::size_t>(l.height);
    std::vector<std::uint8_t> texels(from, from + 4 * n);
    if (light->projector.mode == facet::ProjectorMode::gobo) {
      for (std::size_t k = 0; k < n; ++k) {
        std::uint8_t* p = texels.data() + 4 * k;
        const auto y = static_cast<std::uint8_t>(std::lround(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]));
        p[0] = p[1] = p[2] = y;
      }
    }
    glGenTextures(1, &g.projector);
    glBindTexture(GL_TEXTURE_2D, g.projector);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    const GLint format = t.encoding == facet::TextureEncoding::srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8;
    glTexImage2D(GL_TEXTURE_2D, 0, format, l.width, l.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
    const bool nearest = t.filter == facet::TextureFilter::nearest;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, nearest ? GL_NEAREST : GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, nearest ? GL_NEAREST : GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    const GLfloat black[4] = {0, 0, 0, 1};
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, black);
  }
  g.dot3.assign(s.objects.size(), {});
  if (!light || light->type != facet::LightType::directional) return;
  const Eigen::Vector3d to_light = -light->direction.cast<double>().normalized();
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const facet::Instance& o = s.objects[i];
    const facet::Mesh& mesh = s.meshes[o.mesh].mesh;
    if (s.materials[o.material].normal_texture == facet::kNoTexture || mesh.tangents.size() != mesh.positions.size()) continue;
    const Eigen::Matrix3d m = o.model.topLeftCorner<3, 3>().cast<double>();
    const Eigen::Matrix3d normal_matrix = m.inverse().transpose();
    std::vector<float>& c = g.dot3[i];
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const Eigen::Vector3d n = (normal_matrix * mesh.normals[v].cast<double>()).normalized();
      const Eigen::Vector3d t = (m * mesh.tangents[v].head<3>().cast<double>()).normalized();
      const Eigen::Vector3d b = double(mesh.tangents[v].w()) * n.cross(t);
      const Eigen::Vector3d l(to_light.dot(t), to_light.dot(b), to_light.dot(n));
      c.insert(c.end(), {float(0.5 + 0.5 * l.x()), float(0.5 + 0.5 * l.y()), float(0.5 + 0.5 * l.z()), 1.0f});
    }
  }
}

}  // namespace

GlScene gl_prepare(const facet::Scene& s, bool phong) {
  GlScene g;
  g.textures.resize(s.textures.size());
  if (!g.textures.empty()) glGenTextures(static_cast<GLsizei>(g.textures.size()), g.textures.data());
  for (std::size_t i = 0; i < s.textures.size(); ++i) {
    const facet::Texture& t = s.textures[i];
    glBindTexture(GL_TEXTURE_2D, g.textures[i]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // sRGB textures as GL_SRGB8_ALPHA8 (GL 2.1, EXT_texture_sRGB): decoded per texel, then filtered.
    const GLint format = t.encoding == facet::TextureEncoding::srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8;
    for (std::size_t k = 0; k < t.levels.size(); ++k) {
      const facet::TextureLevel& l = t.levels[k];
      glTexImage2D(GL_TEXTURE_2D, static_cast<GLint>(k), format, l.width, l.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                   t.texels.data() + l.offset);
    }
    gl_sampling(t);
  }
  // Emission units: emissive x texel (8-bit, saturated: facet saturates the sum, and the rest of
  // it is >= 0), alpha 1 (GL_ADD multiplies the alphas); without a texture, one texel of the colour.
  g.emission.assign(s.materials.size(), 0);
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const facet::Material& m = s.materials[i];
    if (!facet::adds_emission_after_texture(m)) continue;
    glGenTextures(1, &g.emission[i]);
    glBindTexture(GL_TEXTURE_2D, g.emission[i]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    auto scaled = [&m](const std::uint8_t* texel, std::uint8_t* out) {
      for (int c = 0; c < 3; ++c) {
        const double v = double(m.emissive[c]) * (texel ? texel[c] / 255.0 : 1.0);
        out[c] = static_cast<std::uint8_t>(std::lround(255.0 * std::min(v, 1.0)));
      }
      out[3] = 255;
    };
    if (m.emissive_texture == facet::kNoTexture) {
      std::uint8_t texel[4];
      scaled(nullptr, texel);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, texel);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      continue;
    }
    const facet::Texture& t = s.textures[static_cast<std::size_t>(m.emissive_texture)];
    std::vector<std::uint32_t> texels(t.texels.size());  // RGBA bytes, as Texture::texels
    const auto* from = reinterpret_cast<const std::uint8_t*>(t.texels.data());
    auto* to = reinterpret_cast<std::uint8_t*>(texels.data());
    for (std::size_t k = 0; k < texels.size(); ++k) scaled(from + 4 * k, to + 4 * k);
    for (std::size_t k = 0; k < t.levels.size(); ++k) {
      const facet::TextureLevel& l = t.levels[k];
      glTexImage2D(GL_TEXTURE_2D, static_cast<GLint>(k), GL_RGBA8, l.width, l.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                   texels.data() + l.offset);
    }
    gl_sampling(t);
  }
  // Environment units: the map's texels pre-combined with the strength where GL's environment
  // cannot scale them (add: k E under GL_ADD; modulate: 1 - k + k E under GL_MODULATE; mix: E
  // under GL_COMBINE's INTERPOLATE with k as the constant), alpha 1. Cube faces go up top row
  // first, as GL reads a face (facet stores textures bottom row first); sphere and normal maps as
  // they are (GL's t = 0 is the bottom row, as facet's).
  g.environment.assign(s.materials.size(), 0);
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const facet::Environment& e = s.materials[i].environment;
    if (e.mode == facet::EnvironmentMode::none) continue;
    const bool cube = e.mode == facet::EnvironmentMode::cube;
    const GLenum target = cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D;
    glGenTextures(1, &g.environment[i]);
    glBindTexture(target, g.environment[i]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (int f = 0; f < (cube ? 6 : 1); ++f) {
      const facet::Texture& t = s.textures[static_cast<std::size_t>(e.maps[f])];
      const int w = t.levels[0].width, h = t.levels[0].height;
      std::vector<std::uint8_t> texels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
      const auto* from = reinterpret_cast<const std::uint8_t*>(t.texels.data());
      for (int y = 0; y < h; ++y) {
        const int row = cube ? h - 1 - y : y;
        for (int x = 0; x < w; ++x) {
          const std::uint8_t* in = from + 4 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x));
          std::uint8_t* out = texels.data() + 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x));
          for (int c = 0; c < 3; ++c) {
            const double v = in[c] / 255.0, k = e.strength;
            const double scaled = e.blend == facet::EnvironmentBlend::add ? k * v
                                  : e.blend == facet::EnvironmentBlend::modulate ? 1.0 - k + k * v
                                                                               : v;
            out[c] = static_cast<std::uint8_t>(std::lround(255.0 * scaled));
          }
          out[3] = 255;
        }
      }
      glTexImage2D(cube ? GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f) : GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA,
                   GL_UNSIGNED_BYTE, texels.data());
    }
    const bool nearest = s.textures[static_cast<std::size_t>(e.maps[0])].filter == facet::TextureFilter::nearest;
    glTexParameteri(target, GL_TEXTURE_MAX_LEVEL, 0);  // level 0, as facet reads environment maps
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, nearest ? GL_NEAREST : GL_LINEAR);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, nearest ? GL_NEAREST : GL_LINEAR);
    glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    if (cube) glTexParameteri(target, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  }
  if (phong) gl_prepare_per_pixel(s, g);
  g.order = facet::draw_order(s);
  for (const auto& o : s.objects) {
    const facet::Mesh& mesh = s.meshes[o.mesh].mesh;
    std::vector<float> c;
    for (const facet::Color3& v : mesh.colors) c.insert(c.end(), {v.x(), v.y(), v.z(), s.materials[o.material].alpha});
    g.colours.push_back(std::move(c));
  }
  return g;
}

void gl_release(GlScene& g) {
  if (!g.textures.empty()) glDeleteTextures(static_cast<GLsizei>(g.textures.size()), g.textures.data());
  g.textures.clear();
  for (GLuint& t : g.emission)
    if (t) glDeleteTextures(1, &t);
  g.emission.clear();
  for (GLuint& t : g.environment)
    if (t) glDeleteTextures(1, &t);
  g.environment.clear();
  if (g.projector) glDeleteTextures(1, &g.projector);
  g.projector = 0;
}

namespace {

// Texture unit 1: the environment map through texgen (GL 2.1 §2.11.4), or off.
void gl_environment(const facet::Scene& s, const GlScene& g, const facet::Material& m, std::size_t material) {
  glActiveTexture(GL_TEXTURE1);
  glClientActiveTexture(GL_TEXTURE1);
  glDisableClientState(GL_TEXTURE_COORD_ARRAY);
  glDisable(GL_TEXTURE_2D);
  glDisable(GL_TEXTURE_CUBE_MAP);
  for (GLenum c : {GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R}) glDisable(c);
  const facet::Environment& e = m.environment;
  if (e.mode == facet::EnvironmentMode::none) return;
  const bool cube = e.mode == facet::EnvironmentMode::cube;
  glEnable(cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D);
  glBindTexture(cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D, g.environment[material]);
  const GLint mode = e.mode == facet::EnvironmentMode::sphere ? GL_SPHERE_MAP
                     : cube                                    ? GL_REFLECTION_MAP
                                                               : GL_NORMAL_MAP;
  for (GLenum c : {GL_S, GL_T, GL_R}) {
    if (c == GL_R && mode == GL_SPHERE_MAP) break;  // a sphere map generates s and t only
    glTexGeni(c, GL_TEXTURE_GEN_MODE, mode);
    glEnable(c == GL_S ? GL_TEXTURE_GEN_S : c == GL_T ? GL_TEXTURE_GEN_T : GL_TEXTURE_GEN_R);
  }
  glMatrixMode(GL_TEXTURE);
  glLoadIdentity();
  if (cube) {  // world space: the view's inverse rotation
    const facet::Mat4 view = facet::view_matrix(s.camera);
    facet::Mat4 to_world = facet::Mat4::Identity();
    to_world.topLeftCorner<3, 3>() = view.topLeftCorner<3, 3>().transpose();
    glLoadMatrixf(to_world.data());
  } else if (e.mode == facet::EnvironmentMode::normal) {  // (s, t) = n / 2 + 1/2
    glTranslatef(0.5f, 0.5f, 0.0f);
    glScalef(0.5f, 0.5f, 1.0f);
  }
  glMatrixMode(GL_MODELVIEW);
  if (e.blend == facet::EnvironmentBlend::mix) {  // C (1 - k) + k E: INTERPOLATE(E, C, k)
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_INTERPOLATE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE0_RGB, GL_TEXTURE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE1_RGB, GL_PREVIOUS);
    glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE2_RGB, GL_CONSTANT);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_RGB, GL_SRC_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND1_RGB, GL_SRC_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND2_RGB, GL_SRC_ALPHA);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_ALPHA, GL_REPLACE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE0_ALPHA, GL_PREVIOUS);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_ALPHA, GL_SRC_ALPHA);
    const GLfloat k[4] = {0, 0, 0, e.strength};
    glTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, k);
  } else {
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, e.blend == facet::EnvironmentBlend::add ? GL_ADD : GL_MODULATE);
  }
}

// GL 2.1 state for a material's surface (see the header comment).
void gl_surface(const facet::Scene& s, const GlScene& g, std::size_t object) {
  const facet::Instance& o = s.objects[object];
  const facet::Material& m = s.materials[o.material];
  const facet::Mesh& mesh = s.meshes[o.mesh].mesh;
  const bool textured = m.diffuse_texture != facet::kNoTexture;
  glLightModeli(GL_LIGHT_MODEL_COLOR_CONTROL, textured ? GL_SEPARATE_SPECULAR_COLOR : GL_SINGLE_COLOR);
  // Unit 0: the diffuse texture; unit 1: the environment map (texgen); unit 2: the emission after
  // them (GL_ADD), at the diffuse texture's coordinates and scale.
  auto unit = [&](GLenum which, GLuint texture, GLint env) {
    glActiveTexture(which);
    glClientActiveTexture(which);
    if (texture) {
      glEnable(GL_TEXTURE_2D);
      glBindTexture(GL_TEXTURE_2D, texture);
      glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, env);
      glMatrixMode(GL_TEXTURE);
      glLoadIdentity();
      glScalef(m.uv_scale.x(), m.uv_scale.y(), 1.0f);
      glMatrixMode(GL_MODELVIEW);
      glEnableClientState(GL_TEXTURE_COORD_ARRAY);
      glTexCoordPointer(2, GL_FLOAT, sizeof(facet::Vec2), mesh.uvs.data());
    } else {
      glDisable(GL_TEXTURE_2D);
      glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    }
  };
  const GLint env[] = {GL_MODULATE, GL_REPLACE, GL_DECAL, GL_ADD};
  unit(GL_TEXTURE2, g.emission[o.material], GL_ADD);
  gl_environment(s, g, m, o.material);
  unit(GL_TEXTURE0, textured ? g.textures[static_cast<std::size_t>(m.diffuse_texture)] : 0,
       env[static_cast<int>(m.texture_mode)]);
  if (!mesh.colors.empty()) {
    glEnable(GL_COLOR_MATERIAL);
    glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    glEnableClientState(GL_COLOR_ARRAY);
    glColorPointer(4, GL_FLOAT, 0, g.colours[object].data());
  } else {
    glDisable(GL_COLOR_MATERIAL);
    glDisableClientState(GL_COLOR_ARRAY);
  }
  if (m.blend == facet::BlendMode::opaque) {
    glDisable(GL_BLEND);
  } else {
    glEnable(GL_BLEND);
    glBlendEquation(m.blend == facet::BlendMode::subtract ? GL_FUNC_REVERSE_SUBTRACT : GL_FUNC_ADD);
    switch (m.blend) {
      case facet::BlendMode::alpha: glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA); break;
      case facet::BlendMode::premultiplied: glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); break;
      case facet::BlendMode::multiply: glBlendFunc(GL_DST_COLOR, GL_ZERO); break;
      default: glBlendFunc(GL_ONE, GL_ONE); break;  // add, subtract
    }
  }
  const bool depth_write = m.depth_write == facet::DepthWrite::on ||
                           (m.depth_write == facet::DepthWrite::automatic && m.blend == facet::BlendMode::opaque);
  glDepthMask(depth_write ? GL_TRUE : GL_FALSE);
  // Alpha to coverage: GL ignores it without a multisampled framebuffer, as facet at one sample.
  if (m.alpha_to_coverage) {
    glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  } else {
    glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  }
  if (m.alpha_cutoff > 0) {
    glEnable(GL_ALPHA_TEST);
    glAlphaFunc(GL_GEQUAL, m.alpha_cutoff);
  } else {
    glDisable(GL_ALPHA_TEST);
  }
}

// Texture unit 3: the projector (GL's projected texture: eye-linear texgen whose planes, given
// under the view matrix, generate world coordinates; the texture matrix takes them into the
// light's view, (s q, t q, 0, q) = (x / (2 tan c) + q / 2, y / (2 tan c) + q / 2, 0, -z), facet's
// s = 1/2 + x / (2 |z| tan c) after the division), modulating the whole fragment; or off.
void gl_projector(const facet::Scene& s, const GlScene& g) {
  glActiveTexture(GL_TEXTURE3);
  const GLenum coords[4] = {GL_S, GL_T, GL_R, GL_Q};
  const GLenum gens[4] = {GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R, GL_TEXTURE_GEN_Q};
  if (!g.projector) {
    glDisable(GL_TEXTURE_2D);
    for (GLenum c : gens) glDisable(c);
    glActiveTexture(GL_TEXTURE0);
    return;
  }
  const facet::Light& light = *only_light(s);
  glEnable(GL_TEXTURE_2D);
  glBindTexture(GL_TEXTURE_2D, g.projector);
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
  for (int k = 0; k < 4; ++k) {
    GLfloat plane[4] = {0, 0, 0, 0};
    plane[k] = 1;
    glTexGeni(coords[k], GL_TEXTURE_GEN_MODE, GL_EYE_LINEAR);
    glTexGenfv(coords[k], GL_EYE_PLANE, plane);  // the modelview is the view: world coordinates
    glEnable(gens[k]);
  }
  // The light's view: looking along its direction, world +y up (+x within 8 degrees of the
  // vertical), as facet's spot shadow maps and projectors.
  const Eigen::Vector3d f = light.direction.cast<double>().normalized();
  const Eigen::Vector3d up = std::abs(f.y()) < 0.99 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d side = f.cross(up).normalized(), u = side.cross(f);
  const Eigen::Vector3d eye = light.position.cast<double>();
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = side.transpose();
  view.block<1, 3>(1, 0) = u.transpose();
  view.block<1, 3>(2, 0) = -f.transpose();
  view(0, 3) = -side.dot(eye), view(1, 3) = -u.dot(eye), view(2, 3) = f.dot(eye);
  const double a = 0.5 / std::tan(std::min(double(light.spot_cutoff_deg), 89.0) * 3.14159265358979323846 / 180.0);
  Eigen::Matrix4d bias = Eigen::Matrix4d::Zero();
  bias(0, 0) = a, bias(0, 2) = -0.5;
  bias(1, 1) = a, bias(1, 2) = -0.5;
  bias(3, 2) = -1;
  const Eigen::Matrix4f texture = (bias * view).cast<float>();
  glMatrixMode(GL_TEXTURE);
  glLoadMatrixf(texture.data());
  glMatrixMode(GL_MODELVIEW);
  glActiveTexture(GL_TEXTURE0);
}

// DOT3 bump mapping for a normal-mapped object (--shading phong): unlit, the vertex colour the
// tangent-space light vector (gl_prepare_per_pixel); unit 0 dots it with the normal map
// (4 ((r0 - 1/2)(r1 - 1/2) + ...), clamped to [0, 1]), unit 1 multiplies by the material's diffuse
// times the light's. Returns false (GL state untouched) for other objects.
bool gl_dot3(const facet::Scene& s, const GlScene& g, std::size_t object) {
  if (g.dot3.empty() || g.dot3[object].empty()) {
    glEnable(GL_LIGHTING);
    return false;
  }
  const facet::Instance& o = s.objects[object];
  const facet::Material& m = s.materials[o.material];
  const facet::Mesh& mesh = s.meshes[o.mesh].mesh;
  const facet::Light& light = *only_light(s);
  glDisable(GL_LIGHTING);
  glDisable(GL_COLOR_MATERIAL);
  glEnableClientState(GL_COLOR_ARRAY);
  glColorPointer(4, GL_FLOAT, 0, g.dot3[object].data());
  const GLuint map = g.textures[static_cast<std::size_t>(m.normal_texture)];
  for (GLenum unit : {GL_TEXTURE0, GL_TEXTURE1}) {
    glActiveTexture(unit);
    glClientActiveTexture(unit);
    for (GLenum c : {GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R, GL_TEXTURE_GEN_Q}) glDisable(c);
    glDisable(GL_TEXTURE_CUBE_MAP);
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, map);  // unit 1 reads no texel, but a unit without a texture is off
    glMatrixMode(GL_TEXTURE);
    glLoadIdentity();
    glScalef(m.uv_scale.x(), m.uv_scale.y(), 1.0f);
    glMatrixMode(GL_MODELVIEW);
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glTexCoordPointer(2, GL_FLOAT, sizeof(facet::Vec2), mesh.uvs.data());
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_ALPHA, GL_REPLACE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE0_ALPHA, GL_PRIMARY_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_ALPHA, GL_SRC_ALPHA);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_RGB, GL_SRC_COLOR);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND1_RGB, GL_SRC_COLOR);
    if (unit == GL_TEXTURE0) {
      glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_DOT3_RGB);
      glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE0_RGB, GL_TEXTURE);
      glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE1_RGB, GL_PRIMARY_COLOR);
    } else {
      glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_MODULATE);
      glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE0_RGB, GL_PREVIOUS);
      glTexEnvi(GL_TEXTURE_ENV, GL_SOURCE1_RGB, GL_CONSTANT);
      const facet::Color3 k = m.diffuse.cwiseProduct(light.diffuse).cwiseMin(1.0f);
      const GLfloat constant[4] = {k.x(), k.y(), k.z(), 1};
      glTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, constant);
    }
  }
  glActiveTexture(GL_TEXTURE0);
  glClientActiveTexture(GL_TEXTURE0);
  return true;
}

}  // namespace

// Draws the scene with fixed-function OpenGL into the current OSMesa buffer.
void gl_draw(const facet::Scene& s, const GlScene& g, int w, int h) {
  glViewport(0, 0, w, h);
  glClearColor(0, 0, 0, 1);
  glClearDepth(1.0);
  glDepthMask(GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (s.fog.mode == facet::FogMode::none) {
    glDisable(GL_FOG);
  } else {
    glEnable(GL_FOG);
    const GLint mode[] = {GL_LINEAR, GL_LINEAR, GL_EXP, GL_EXP2};
    glFogi(GL_FOG_MODE, mode[static_cast<int>(s.fog.mode)]);
    const GLfloat colour[4] = {s.fog.color.x(), s.fog.color.y(), s.fog.color.z(), 1};
    glFogfv(GL_FOG_COLOR, colour);
    glFogf(GL_FOG_START, s.fog.start);
    glFogf(GL_FOG_END, s.fog.end);
    glFogf(GL_FOG_DENSITY, s.fog.density);
  }
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  glShadeModel(GL_SMOOTH);
  glEnable(GL_LIGHTING);
  glEnable(GL_NORMALIZE);
  const float aspect = s.camera.aspect > 0 ? s.camera.aspect : float(w) / float(h);
  const facet::Mat4 proj = facet::projection_matrix(s.camera, aspect);
  const facet::Mat4 view = facet::view_matrix(s.camera);
  glMatrixMode(GL_PROJECTION);
  if (s.camera.projection == facet::Projection::orthographic) {
    // GL's own box, not facet's matrix: the comparison checks facet's projection too.
    const double hh = s.camera.half_height, hw = hh * double(aspect);
    glLoadIdentity();
    glOrtho(-hw, hw, -hh, hh, s.camera.near, s.camera.far);
  } else {
    glLoadMatrixf(proj.data());  // Eigen is column-major, like OpenGL
  }
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixf(view.data());  // lights are given in world space: GL moves them to eye space
  const GLfloat global[4] = {s.global_ambient.x(), s.global_ambient.y(), s.global_ambient.z(), 1};
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, global);
  glLightModeli(GL_LIGHT_MODEL_LOCAL_VIEWER, s.viewer == facet::ViewerMode::local ? GL_TRUE : GL_FALSE);
  glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, s.two_sided ? GL_TRUE : GL_FALSE);
  for (int i = 0; i < 8; ++i) glDisable(GL_LIGHT0 + i);
  for (std::size_t i = 0; i < s.lights.size(); ++i) {
    const facet::Light& l = s.lights[i];
    const GLenum id = GL_LIGHT0 + static_cast<GLenum>(i);
    if (!l.enabled) continue;
    glEnable(id);
    gl_colour(id, GL_AMBIENT, l.ambient, 1, false);
    gl_colour(id, GL_DIFFUSE, l.diffuse, 1, false);
    gl_colour(id, GL_SPECULAR, l.specular, 1, false);
    if (l.type == facet::LightType::directional) {
      const facet::Vec3 to_light = -l.direction.normalized();
      const GLfloat p[4] = {to_light.x(), to_light.y(), to_light.z(), 0};
      glLightfv(id, GL_POSITION, p);
    } else {
      const GLfloat p[4] = {l.position.x(), l.position.y(), l.position.z(), 1};
      glLightfv(id, GL_POSITION, p);
    }
    glLightf(id, GL_CONSTANT_ATTENUATION, l.type == facet::LightType::directional ? 1 : l.constant_attenuation);
    glLightf(id, GL_LINEAR_ATTENUATION, l.type == facet::LightType::directional ? 0 : l.linear_attenuation);
    glLightf(id, GL_QUADRATIC_ATTENUATION, l.type == facet::LightType::directional ? 0 : l.quadratic_attenuation);
    if (l.type == facet::LightType::spot) {
      const GLfloat d[3] = {l.direction.x(), l.direction.y(), l.direction.z()};
      glLightfv(id, GL_SPOT_DIRECTION, d);
      glLightf(id, GL_SPOT_CUTOFF, l.spot_cutoff_deg);
      glLightf(id, GL_SPOT_EXPONENT, l.spot_exponent);
    } else {
      glLightf(id, GL_SPOT_CUTOFF, 180);
    }
  }
  gl_projector(s, g);  // with the view as the modelview
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_NORMAL_ARRAY);
  for (const std::size_t i : g.order) {  // as facet draws them (the scene's transparent order)
    const facet::Instance& o = s.objects[i];
    const facet::Material& m = s.materials[o.material];
    gl_surface(s, g, i);
    gl_dot3(s, g, i);
    // Emission after the texture comes from texture unit 2 (gl_surface).
    gl_colour(GL_FRONT_AND_BACK, GL_EMISSION, facet::adds_emission_after_texture(m) ? facet::Color3::Zero() : m.emissive, m.alpha, true);
    gl_colour(GL_FRONT_AND_BACK, GL_AMBIENT, m.ambient, m.alpha, true);
    gl_colour(GL_FRONT_AND_BACK, GL_DIFFUSE, m.diffuse, m.alpha, true);
    gl_colour(GL_FRONT_AND_BACK, GL_SPECULAR, m.specular, m.alpha, true);
    glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, m.shininess);
    const facet::Mat4 mv = view * o.model;
    glLoadMatrixf(mv.data());
    const facet::Mesh& mesh = s.meshes[o.mesh].mesh;
    glVertexPointer(3, GL_FLOAT, sizeof(facet::Vec3), mesh.positions.data());
    glNormalPointer(GL_FLOAT, sizeof(facet::Vec3), mesh.normals.data());
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * mesh.triangles.size()), GL_UNSIGNED_INT, mesh.triangles.data());
  }
  glFinish();
}

}  // namespace gl_compare
