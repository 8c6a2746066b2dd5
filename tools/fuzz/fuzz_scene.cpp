// Fuzzes the JSON scene parser; accepted scenes must validate and, unless check_render refuses
// them (frame limits, memory budget) with the very message render() then gives, render into a
// small guarded image. Loads run under a 256 MiB budget, so no input can take more than that in
// meshes (the fuzzer's RSS limit is 3 GiB). (OBJ and image paths resolve in a directory that
// does not exist: they fail as missing files.)
//
// Textures as bytes: an input "JSON \0 IMAGE" also decodes IMAGE (PNG or JPEG, under a 64 MiB
// budget) with decode_texture; a refusal must name the image; a decoded texture must validate, and
// is then put on every material of the scene (when every object's mesh has texture coordinates),
// and on some inputs as every material's environment map (sphere, or cube when square), as a
// normal, bump and occlusion map (with tangents generated) and as every spot light's projector,
// so the decoders' output goes through the samplers, the pixel program and the lighting kernels.
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::size_t split = input.find('\0');
  const std::string text = input.substr(0, split);
  facet::LoadOptions load;
  load.memory_budget_bytes = std::uint64_t{256} << 20;
  facet::Result<facet::Scene> scene = facet::parse_scene_json(text, "fuzz.json", "/nonexistent-facet-fuzz", load);
  if (split != std::string::npos) {
    const auto* image = reinterpret_cast<const std::uint8_t*>(input.data() + split + 1);
    facet::TextureOptions options;
    options.filter = static_cast<facet::TextureFilter>(size % 3);
    options.wrap = static_cast<facet::TextureWrap>((size / 3) % 3);
    options.memory_budget_bytes = std::uint64_t{64} << 20;
    facet::Result<facet::Texture> texture =
        facet::decode_texture(std::span<const std::uint8_t>(image, size - split - 1), "fuzz-image", "fuzz", options);
    if (!texture.ok()) {
      if (texture.status().message().find("fuzz-image") == std::string::npos) {
        facet::fuzz::broken("an image error that does not name the image");
      }
    } else {
      if (!facet::validate_texture(*texture).ok()) facet::fuzz::broken("decode_texture returned an invalid texture");
      if (scene.ok()) {
        bool uvs = true;
        for (const auto& o : scene->objects) {
          const facet::Mesh& m = scene->meshes[o.mesh].mesh;
          uvs = uvs && m.uvs.size() == m.positions.size();
        }
        const auto index = static_cast<std::int32_t>(scene->textures.size());
        scene->textures.push_back(std::move(*texture));
        // As an environment map on every material: a sphere map, or (square) every face of a cube,
        // or (not square) a cube converted from it as an equirectangular picture.
        const bool square = scene->textures.back().width() == scene->textures.back().height();
        std::int32_t first_face = index;
        if (!square && (size & 32)) {
          facet::TextureOptions faces_options;
          faces_options.filter = facet::TextureFilter::bilinear;
          faces_options.wrap = facet::TextureWrap::clamp;
          faces_options.memory_budget_bytes = std::uint64_t{4} << 20;
          const int face = 1 + static_cast<int>(size % 24);
          facet::Result<std::vector<facet::Texture>> faces =
              facet::cube_faces_from_equirect(scene->textures.back(), face, "fuzz", faces_options);
          if (!faces.ok()) facet::fuzz::broken("a decoded picture that cube_faces_from_equirect refuses");
          first_face = static_cast<std::int32_t>(scene->textures.size());
          for (auto& f : *faces) {
            if (!facet::validate_texture(f).ok()) facet::fuzz::broken("cube_faces_from_equirect made an invalid face");
            scene->textures.push_back(std::move(f));
          }
        }
        for (auto& m : scene->materials) {
          if (!(size & 16)) break;
          m.environment.mode = size & 32 ? facet::EnvironmentMode::cube : facet::EnvironmentMode::sphere;
          for (int f = 0; f < 6; ++f) {
            m.environment.maps[f] = m.environment.mode == facet::EnvironmentMode::cube ? first_face + (square ? 0 : f)
                                    : f == 0                                       ? index
                                                                                   : facet::kNoTexture;
          }
          m.environment.blend = static_cast<facet::EnvironmentBlend>((size >> 6) % 3);
        }
        if (uvs) {
          for (auto& m : scene->materials) {
            m.diffuse_texture = index;
            if (size & 8) {  // and as the emissive texture (the emission after the texture)
              m.emissive_texture = index;
              if (m.emissive == facet::Color3::Zero()) m.emissive = facet::Color3(0.5f, 0.25f, 1.0f);
            }
            if (size & 128) m.normal_texture = index, m.normal_scale = (size & 256) ? -2.0f : 1.0f;
            if (size & 512) m.bump_texture = index, m.bump_scale = 5.0f;
            if (size & 1024) m.occlusion_texture = index;
          }
          if (!facet::generate_missing_tangents(*scene).ok()) facet::fuzz::broken("tangents refused for a valid mesh");
        }
        int projectors = 0;
        for (auto& l : scene->lights) {
          if (l.type == facet::LightType::spot && l.enabled && projectors < facet::kMaxProjectors && (size & 2048)) {
            l.projector.texture = index, ++projectors;
            l.projector.mode = (size & 4096) ? facet::ProjectorMode::gobo : facet::ProjectorMode::modulate;
          }
        }
      }
    }
  }
  if (!scene.ok()) {
    if (scene.status().message().rfind("fuzz.json", 0) != 0) facet::fuzz::broken("an error that does not name the file");
    return 0;
  }
  if (!facet::validate_scene(*scene).ok()) facet::fuzz::broken("parse_scene_json returned an invalid scene");
  std::size_t vertices = 0;
  for (const auto& o : scene->objects) vertices += scene->meshes[o.mesh].mesh.vertex_count();
  if (vertices > 200000) return 0;  // valid, but too slow to render at fuzzing speed
  facet::fuzz::GuardedImage image(24, 16, facet::PixelFormat::rgba8, 3, false);
  facet::RenderOptions options;
  options.threads = 1;
  options.shading = static_cast<facet::ShadingMode>(size % 3);
  options.vertex_relief = (size / 3) % 2 != 0;  // Gouraud reads the maps per vertex
  options.samples = (size / 6) % 2 != 0 ? 8 : 1;  // multisampled for half the inputs
  facet::Renderer renderer;
  const facet::Status checked = facet::check_render(*scene, options, 24, 16);
  const facet::Status rendered = renderer.render(*scene, options, image.view());
  if (checked.message() != rendered.message()) facet::fuzz::broken("check_render and render disagree");
  if (!checked.ok()) return 0;  // a frame limit or the memory budget, the same for both
  image.check();
  return 0;
}
