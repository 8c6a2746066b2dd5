// The C API: per-vertex data and textures.
#include "c_api/handles.hpp"

using namespace facet::c_api;  // NOLINT(google-build-using-namespace): the C API's shared helpers

namespace {
// Per-vertex uvs (colours = false) or colours of mesh_id, validated as validate_mesh would.
enum class VertexData { uvs, colours, tangents, lightmap_uvs };
facet_status set_vertex_data(facet_scene* scene, uint32_t mesh_id, const float* data, VertexData what) {
  const bool colours = what == VertexData::colours;
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (mesh_id >= scene->scene.meshes.size()) return fail(scene->error, "mesh_id", "no such mesh");
    facet::Mesh& mesh = scene->scene.meshes[mesh_id].mesh;
    facet::Mesh candidate;  // checked on a copy of the arrays' shape: a failure changes nothing
    candidate.positions = mesh.positions;
    candidate.normals = mesh.normals;
    candidate.triangles = mesh.triangles;
    const std::size_t n = data ? mesh.vertex_count() : 0;
    if (what == VertexData::tangents) {
      candidate.tangents.resize(n);
      for (std::size_t v = 0; v < n; ++v)
        candidate.tangents[v] = facet::Vec4(data[4 * v], data[4 * v + 1], data[4 * v + 2], data[4 * v + 3]);
    } else if (colours) {
      candidate.colors.resize(n);
      for (std::size_t v = 0; v < n; ++v) candidate.colors[v] = facet::Color3(data[3 * v], data[3 * v + 1], data[3 * v + 2]);
    } else if (what == VertexData::lightmap_uvs) {
      candidate.lightmap_uvs.resize(n);
      for (std::size_t v = 0; v < n; ++v) candidate.lightmap_uvs[v] = facet::Vec2(data[2 * v], data[2 * v + 1]);
    } else {
      candidate.uvs.resize(n);
      for (std::size_t v = 0; v < n; ++v) candidate.uvs[v] = facet::Vec2(data[2 * v], data[2 * v + 1]);
    }
    if (facet::Status st = facet::validate_mesh(candidate, "meshes[" + std::to_string(mesh_id) + "]"); !st.ok()) {
      return report(scene->error, st);
    }
    if (what == VertexData::tangents) {
      mesh.tangents = std::move(candidate.tangents);
    } else if (colours) {
      mesh.colors = std::move(candidate.colors);
    } else if (what == VertexData::lightmap_uvs) {
      mesh.lightmap_uvs = std::move(candidate.lightmap_uvs);
    } else {
      mesh.uvs = std::move(candidate.uvs);
    }
    return report(scene->error, {});
  });
}

facet_status add_texture(facet_scene* scene, facet::Result<facet::Texture> texture, uint32_t* texture_id) {
  if (!texture) return report(scene->error, texture.status());
  const auto id = static_cast<std::uint32_t>(scene->scene.textures.size());
  scene->scene.textures.push_back(std::move(*texture));
  if (texture_id) *texture_id = id;
  return report(scene->error, {});
}

facet::TextureOptions texture_options(facet_texture_filter filter, facet_texture_wrap wrap) {
  facet::TextureOptions o;
  o.filter = static_cast<facet::TextureFilter>(filter);
  o.wrap = static_cast<facet::TextureWrap>(wrap);
  return o;
}
}  // namespace

extern "C" {

facet_status facet_scene_set_mesh_uvs(facet_scene* scene, uint32_t mesh_id, const float* uvs) {
  return set_vertex_data(scene, mesh_id, uvs, VertexData::uvs);
}

facet_status facet_scene_set_mesh_lightmap_uvs(facet_scene* scene, uint32_t mesh_id, const float* uvs) {
  return set_vertex_data(scene, mesh_id, uvs, VertexData::lightmap_uvs);
}

facet_status facet_scene_set_mesh_tangents(facet_scene* scene, uint32_t mesh_id, const float* xyzw) {
  return set_vertex_data(scene, mesh_id, xyzw, VertexData::tangents);
}

facet_status facet_scene_generate_tangents(facet_scene* scene, uint32_t mesh_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (mesh_id >= scene->scene.meshes.size()) return fail(scene->error, "mesh_id", "no such mesh");
    facet::Mesh candidate = scene->scene.meshes[mesh_id].mesh;  // a failure changes nothing
    if (facet::Status st = facet::generate_tangents(candidate); !st.ok()) return report(scene->error, st);
    scene->scene.meshes[mesh_id].mesh = std::move(candidate);
    return report(scene->error, {});
  });
}

facet_status facet_scene_set_mesh_colors(facet_scene* scene, uint32_t mesh_id, const float* rgb) {
  return set_vertex_data(scene, mesh_id, rgb, VertexData::colours);
}

facet_status facet_scene_add_texture_rgba8(facet_scene* scene, const uint8_t* rgba, int width, int height,
                                           facet_texture_filter filter, facet_texture_wrap wrap, uint32_t* texture_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!rgba) return fail(scene->error, "rgba", "null");
    if (filter < FACET_NEAREST || filter > FACET_TRILINEAR) return fail(scene->error, "filter", "unknown texture filter");
    if (wrap < FACET_WRAP_REPEAT || wrap > FACET_WRAP_MIRROR) return fail(scene->error, "wrap", "unknown wrap mode");
    if (width < 1 || height < 1 || width > facet::kMaxTextureDimension || height > facet::kMaxTextureDimension) {
      return fail(scene->error, "width", "a texture is 1 to 16384 texels per side");
    }
    const std::size_t bytes = 4 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    const auto id = static_cast<std::uint32_t>(scene->scene.textures.size());
    return add_texture(scene,
                       facet::make_texture("texture" + std::to_string(id), width, height,
                                           std::span<const std::uint8_t>(rgba, bytes), texture_options(filter, wrap)),
                       texture_id);
  });
}

facet_status facet_scene_load_texture(facet_scene* scene, const char* path, facet_texture_filter filter,
                                      facet_texture_wrap wrap, uint32_t* texture_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!path) return fail(scene->error, "path", "null");
    if (filter < FACET_NEAREST || filter > FACET_TRILINEAR) return fail(scene->error, "filter", "unknown texture filter");
    if (wrap < FACET_WRAP_REPEAT || wrap > FACET_WRAP_MIRROR) return fail(scene->error, "wrap", "unknown wrap mode");
    const auto id = static_cast<std::uint32_t>(scene->scene.textures.size());
    return add_texture(scene, facet::load_texture(path, "texture" + std::to_string(id), texture_options(filter, wrap)),
                       texture_id);
  });
}

facet_status facet_scene_add_texture_encoded(facet_scene* scene, const void* bytes, size_t size,
                                             facet_texture_filter filter, facet_texture_wrap wrap, uint32_t* texture_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (!bytes && size > 0) return fail(scene->error, "bytes", "null with a non-zero size");
    if (filter < FACET_NEAREST || filter > FACET_TRILINEAR) return fail(scene->error, "filter", "unknown texture filter");
    if (wrap < FACET_WRAP_REPEAT || wrap > FACET_WRAP_MIRROR) return fail(scene->error, "wrap", "unknown wrap mode");
    const auto id = static_cast<std::uint32_t>(scene->scene.textures.size());
    const std::string name = "texture" + std::to_string(id);
    return add_texture(scene,
                       facet::decode_texture(std::span<const std::uint8_t>(static_cast<const std::uint8_t*>(bytes), size),
                                             name, name, texture_options(filter, wrap)),
                       texture_id);
  });
}

facet_status facet_scene_set_texture_encoding(facet_scene* scene, uint32_t texture_id, facet_texture_encoding encoding) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (texture_id >= scene->scene.textures.size()) return fail(scene->error, "texture_id", "no such texture");
    const long e = raw(encoding);
    if (e != FACET_ENCODING_LINEAR && e != FACET_ENCODING_SRGB) return fail(scene->error, "encoding", "unknown texture encoding");
    facet::Texture& t = scene->scene.textures[texture_id];
    const auto want = e == FACET_ENCODING_SRGB ? facet::TextureEncoding::srgb : facet::TextureEncoding::linear;
    if (t.encoding == want) return report(scene->error, {});
    // Level 0 again, top row first as make_texture takes it, and the mipmaps rebuilt.
    const int w = t.width(), h = t.height();
    std::vector<std::uint8_t> rgba(4 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    for (int j = 0; j < h; ++j) {
      const std::uint32_t* row = t.texels.data() + static_cast<std::size_t>(h - 1 - j) * static_cast<std::size_t>(w);
      std::uint8_t* out = rgba.data() + 4 * static_cast<std::size_t>(j) * static_cast<std::size_t>(w);
      for (int i = 0; i < w; ++i)
        for (int c = 0; c < 4; ++c) out[4 * i + c] = static_cast<std::uint8_t>(row[i] >> (8 * c));
    }
    facet::TextureOptions o = texture_options(static_cast<facet_texture_filter>(t.filter), static_cast<facet_texture_wrap>(t.wrap));
    o.memory_budget_bytes = 0;
    o.encoding = want;
    facet::Result<facet::Texture> remade = facet::make_texture(t.name, w, h, rgba, o);
    if (!remade) return report(scene->error, remade.status());
    t = std::move(*remade);
    return report(scene->error, {});
  });
}

facet_status facet_scene_texture_encoding(const facet_scene* scene, uint32_t texture_id, facet_texture_encoding* encoding) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  if (!encoding) return fail(scene->error, "encoding", "null");
  if (texture_id >= scene->scene.textures.size()) return fail(scene->error, "texture_id", "no such texture");
  *encoding = scene->scene.textures[texture_id].encoding == facet::TextureEncoding::srgb ? FACET_ENCODING_SRGB
                                                                                         : FACET_ENCODING_LINEAR;
  return FACET_OK;
}

facet_status facet_scene_add_cube_from_equirect_progress(facet_scene* scene, uint32_t texture_id, int face_size,
                                                        int (*progress)(void* user, double done), void* progress_user,
                                                        uint32_t* first_face_id) {
  if (!scene) return FACET_INVALID_ARGUMENT;
  return guarded(&scene->error, [&] {
    if (texture_id >= scene->scene.textures.size()) return fail(scene->error, "texture_id", "no such texture");
    const auto key = std::make_tuple(texture_id, face_size, static_cast<int>(scene->scene.textures[texture_id].encoding));
    if (auto it = scene->equirect_faces.find(key); it != scene->equirect_faces.end()) {
      if (first_face_id) *first_face_id = it->second;
      return report(scene->error, {});
    }
    facet::TextureOptions o;
    o.filter = facet::TextureFilter::bilinear;  // environment maps are read at level 0
    o.wrap = facet::TextureWrap::clamp;
    const auto first = static_cast<std::uint32_t>(scene->scene.textures.size());
    std::function<bool(double)> asked;
    if (progress) asked = [progress, progress_user](double done) { return progress(progress_user, done) != 0; };
    facet::Result<std::vector<facet::Texture>> faces = facet::cube_faces_from_equirect(
        scene->scene.textures[texture_id], face_size, "texture" + std::to_string(first), o, asked);
    if (!faces) return report(scene->error, faces.status());
    for (facet::Texture& f : *faces) scene->scene.textures.push_back(std::move(f));
    scene->equirect_faces.emplace(key, first);
    if (first_face_id) *first_face_id = first;
    return report(scene->error, {});
  });
}

facet_status facet_scene_add_cube_from_equirect(facet_scene* scene, uint32_t texture_id, int face_size,
                                               uint32_t* first_face_id) {
  return facet_scene_add_cube_from_equirect_progress(scene, texture_id, face_size, nullptr, nullptr, first_face_id);
}

}  // extern "C"
