// Per draw of a pass: transform its vertices, light them (Gouraud), its triangles (flat) or
// nothing (Phong: lit per pixel), and assemble its triangles into set-up ranges in parallel.
#include <algorithm>
#include <atomic>

#include <tbb/blocked_range.h>

#include "frame/frame.hpp"
#include "frame/vertex_relief.hpp"
#include "lighting/setup.hpp"
#include "pixel/stages.hpp"

namespace facet {

void Renderer::Impl::ObjectScratch::reserve_generated(std::size_t vertices) {
  for (std::size_t g = 0; g < raster::kGeneratedVaryings.size(); ++g) {
    generated[g].reserve(vertices * static_cast<std::size_t>(raster::width_of(raster::kGeneratedVaryings[g])));
  }
}

void Renderer::Impl::ObjectScratch::reserve(std::size_t vertices, std::size_t triangles, ShadingMode mode,
                                            bool both_faces, bool surfaces) {
  clip.reserve(vertices);
  screen.reserve(vertices);
  if (mode == ShadingMode::gouraud) {
    drawn.reserve(vertices);
    lit_index.reserve(vertices);
    front.reserve(vertices);
    if (both_faces) back.reserve(vertices);
    if (surfaces) {  // a textured object's specular, kept apart; varyings generated at the vertices
      front_spec.reserve(vertices);
      if (both_faces) back_spec.reserve(vertices);
      eye_p.reserve(vertices);
      eye_n.reserve(vertices);
      relief_normals.reserve(vertices);  // RenderOptions::vertex_relief
      reserve_generated(vertices);
    }
    return;
  }
  if (mode == ShadingMode::flat) {
    flat_albedo.reserve(triangles);
    if (surfaces) {
      front_spec.reserve(triangles);
      if (both_faces) back_spec.reserve(triangles);
      reserve_generated(vertices);
    }
  }
  eye_p.reserve(vertices);
  eye_n.reserve(vertices);
  if (mode == ShadingMode::flat) {
    centroid.reserve(triangles);
    face_normal.reserve(triangles);
    front.reserve(triangles);
    if (both_faces) back.reserve(triangles);
  }
}

// Every draw of the running pass: lighting, then assembly into its set-up ranges, numbered in
// draw order.
void Renderer::Impl::set_up_objects(const Scene& scene, const RenderOptions& options) {
  const RenderPass& p = *pass;
  const ShadingMode shading = p.shading;
  range_count = 0;  // counted below, per draw
  if (shaders.size() < units.size()) shaders.resize(units.size());  // grow only: passes differ in draw count
  const bool two_sided = draws.any_two_sided();

  const Eigen::Matrix4d& view = p.view;
  const Eigen::Matrix4d& proj = p.projection;
  LightingOptions lighting;
  lighting.path = options.path;
  lighting.isa = options.isa;
  lighting.pow_tier = options.pow_tier;
  lighting.clamp = !(options.hdr && p.color && p.color->format == PixelFormat::rgba32f);
  lighting.cull_lights = options.cull_lights;
  light_every_vertex = options.light_every_vertex;

  // Set-up ranges, numbered in draw order.
  const std::size_t object_count = units.size();
  first_range.resize(object_count);
  for (std::size_t o = 0; o < object_count; ++o) {
    first_range[o] = range_count;
    range_count += units[o].ranges();
  }
  if (range_triangles.size() < range_count) {  // grows only with the scene
    range_triangles.resize(range_count);
    range_binning.resize(range_count);
    range_pending.resize(range_count);
  }
  object_counts.assign(object_count, {});
  object_scratch.resize(workers.size());
  // Runs of two or more small objects are set up side by side, one task per object (one after
  // another, a scene of a few small objects left the second thread idle for much of the frame).
  // Larger objects are set up one at a time with their chunks and ranges spread over the threads.
  auto small = [&](std::size_t o) {
    const Mesh& mesh = scene.meshes[scene.objects[units[o].object].mesh].mesh;
    const std::size_t lit = shading == ShadingMode::flat ? mesh.triangle_count() : mesh.vertex_count();
    return lit <= kSmallObjectVertices && mesh.triangle_count() <= kSmallObjectTriangles;
  };
  // Which slot sets up which small object depends on the schedule, so every slot's scratch is
  // sized here, on the calling thread, for the largest object it could get: slot 0 for every
  // object (large ones always run on it), the others for every small one. A frame that has run
  // once then allocates nothing, whatever the schedule (tests/alloc).
  std::size_t small_v = 0, small_t = 0, all_v = 0, all_t = 0;
  for (std::size_t o = 0; o < object_count; ++o) {
    const Mesh& mesh = scene.meshes[scene.objects[units[o].object].mesh].mesh;
    all_v = std::max(all_v, mesh.vertex_count());
    all_t = std::max(all_t, mesh.triangle_count());
    if (small(o)) {
      small_v = std::max(small_v, mesh.vertex_count());
      small_t = std::max(small_t, mesh.triangle_count());
    }
  }
  for (std::size_t slot = 0; slot < object_scratch.size(); ++slot) {
    object_scratch[slot].reserve(slot == 0 ? all_v : small_v, slot == 0 ? all_t : small_t, shading, two_sided,
                                 !scene.textures.empty());
  }
  for (std::size_t o = 0; o < object_count;) {
    if (!small(o)) {
      set_up_object(scene, static_cast<std::uint32_t>(o), view, proj, lighting, object_scratch[0], -1);
      ++o;
      continue;
    }
    std::size_t end = o + 1;
    while (end < object_count && small(end)) ++end;
    if (end == o + 1) {  // alone: its own chunks and ranges are the only parallelism
      set_up_object(scene, static_cast<std::uint32_t>(o), view, proj, lighting, object_scratch[0], -1);
      ++o;
      continue;
    }
    arena->parallel_for(tbb::blocked_range<std::size_t>(o, end, 1), [&](const tbb::blocked_range<std::size_t>& r, int slot) {
      for (std::size_t k = r.begin(); k != r.end(); ++k) {
        set_up_object(scene, static_cast<std::uint32_t>(k), view, proj, lighting,
                      object_scratch[static_cast<std::size_t>(slot)], slot);
      }
    });
    o = end;
  }
  for (const ObjectCounts& c : object_counts) {  // in draw order
    if (p.depth_only) break;  // a shadow map's set-up counts as the shadows' time
    stats.vertices_lit += c.vertices_lit;
    stats.vertices_skipped += c.vertices_skipped;
    stats.vertex_lights_evaluated += c.pairs_evaluated;
    stats.vertex_lights_skipped += c.pairs_skipped;
    stats.seconds_lighting += c.seconds_lighting;
    stats.seconds_geometry += c.seconds_geometry;
  }
}

template <class Body>
void Renderer::Impl::for_chunks(std::size_t begin, std::size_t end, std::size_t grain, int slot, const Body& body) {
  auto unit = [&](const tbb::blocked_range<std::size_t>& r, int s) {
    if (cancelled.load(std::memory_order_relaxed)) return;
    body(r, s);
    unit_done();
  };
  if (slot < 0) {
    if (begin < end) arena->parallel_for(tbb::blocked_range<std::size_t>(begin, end, grain), unit);
  } else {
    for (std::size_t b = begin; b < end; b += grain) unit(tbb::blocked_range<std::size_t>(b, std::min(end, b + grain), grain), slot);
  }
}

// One object: lighting, then assembly into its set-up ranges. slot < 0: spread over the threads.
void Renderer::Impl::set_up_object(const Scene& scene, std::uint32_t object, const Eigen::Matrix4d& view,
                                   const Eigen::Matrix4d& proj, const LightingOptions& lighting, ObjectScratch& os,
                                   int slot) {
  const DrawUnit& u = units[object];
  const Instance& inst = scene.objects[u.object];
  prepare_object(scene, inst, view, proj, lighting, object, os, slot);
  const auto geometry_start = Clock::now();
  assemble_object(scene.meshes[inst.mesh].mesh, object, scene.materials[u.material].alpha, os, slot);
  object_counts[object].seconds_geometry += seconds_since(geometry_start);
}

void Renderer::Impl::prepare_object(const Scene& scene, const Instance& inst, const Eigen::Matrix4d& view,
                                    const Eigen::Matrix4d& proj, const LightingOptions& lighting,
                                    std::uint32_t object, ObjectScratch& os, int slot) {
  const ShadingMode shading = pass->shading;
  const bool two_sided = draws.two_sided[object] != 0;
  const Mesh& mesh = scene.meshes[inst.mesh].mesh;
  const DrawUnit& unit = units[object];
  // Arrays are indexed by the mesh's vertex and triangle numbers; a draw fills its own part.
  const std::size_t n = mesh.vertex_count(), v0 = unit.first_vertex, v1 = unit.end_vertex;
  const auto lighting_start = Clock::now();
  std::vector<std::array<float, 4>>& clip = os.clip;
  std::vector<ScreenVertex>& screen = os.screen;
  os.mirrored = inst.model.cast<double>().topLeftCorner<3, 3>().determinant() < 0.0;
  // Clip-space positions.
  const geometry::Mat4Rows mvp = geometry::to_rows(proj * view * inst.model.cast<double>());
  clip.resize(n);
  screen.resize(n);
  // The simd path transforms with its ISA's kernel (bit-identical to the scalar function).
  static_assert(sizeof(Vec3) == 3 * sizeof(float), "the kernels read positions as xyz triples");
  const raster::simd::TransformFunction transform = simd_kernels ? simd_kernels->transform : nullptr;
  for_chunks(v0, v1, kVertexChunk, slot, [&](const tbb::blocked_range<std::size_t>& r, int) {
    if (transform) {
      transform(mvp, mesh.positions.data()->data(), r.begin(), r.end(), pass->assembly.planes, pass->assembly.viewport,
                clip.data(), screen.data());
    } else {
      geometry::transform_vertices(mvp, mesh.positions.data(), r.begin(), r.end(), pass->assembly.planes,
                                   pass->assembly.viewport, clip.data(), screen.data());
    }
  });

  if (pass->depth_only) return;  // a shadow map: positions are all it needs

  lighting::PointShader& shader = shaders[object];
  // The bounds' passes over the positions: a large object spread over the threads (chunks fixed
  // by its vertex count, so the sphere is the same for any thread count).
  // Only when the plan can cull: a point or spot light is on (directional lights are never culled).
  const Scene& lit_by = kind.lights_of(scene);
  const bool cullable = lighting.cull_lights && std::any_of(lit_by.lights.begin(), lit_by.lights.end(), [](const Light& l) {
    return l.enabled && l.type != LightType::directional;
  });
  lighting::EyeSphere bounds{};
  if (cullable) {
    bounds = lighting::eye_bounding_sphere(mesh, view, inst.model, [&](std::size_t chunks, const auto& fn) {
      if (slot >= 0 || chunks == 1) return lighting::chunks_in_turn(chunks, fn);
      arena->parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r, int) {
        for (std::size_t c = r.begin(); c < r.end(); ++c) fn(c);
      });
    });
  }
  // Options were checked in render(), so preparing cannot fail here.
  lighting::LightingFeatures lf = draws.features[object];
  lf.image_light = frame_image_light;
  Material material = scene.materials[unit.material];
  // Emission left out of the lighting: in the parts of a composite frame, or added by the pixel program.
  // (A lightmapped draw has the emission stage for its baked light; its material's emission stays
  // in the lighting unless it is added after the texture.)
  if (kind.without_emission || (draws.programs[object].emission && adds_emission_after_texture(material))) {
    material.emissive = Color3(0.0f, 0.0f, 0.0f);
  }
  (void)shader.prepare(lit_by, view, material, lighting, cullable ? &bounds : nullptr, lf,
                       inst.receive_shadows && has_shadows && !pass->environment_face ? &frame_shadows : nullptr);
  if (kind.kind == FrameKind::Kind::visibility) shader.output_visibility(kind.visibility_lights);
  ObjectCounts& counts = object_counts[object];
  auto count_pairs = [&](std::size_t evaluations) {
    counts.vertices_lit += evaluations;
    counts.pairs_evaluated += evaluations * shader.light_count();
    counts.pairs_skipped += evaluations * shader.culled_lights();
  };
  std::vector<Color3>&front = os.front, &back = os.back;
  std::vector<Vec3>&eye_p = os.eye_p, &eye_n = os.eye_n, &centroid = os.centroid, &face_normal = os.face_normal;

  const bool split = lf.separate_specular;
  // Eye-space positions and normals: flat and Phong light with them, and the pixel stages
  // generate varyings at the vertices from them (GL's texgen).
  const pixel::Draw& draw = draws.programs[object];
  bool generates = false;
  for (const raster::Varying v : raster::kGeneratedVaryings) generates = generates || draw.layout.has(v);
  if (shading != ShadingMode::gouraud || generates) {
    const auto xf = lighting::make_eye_transform<float>(view, inst.model);
    eye_p.resize(n);
    eye_n.resize(n);
    for (std::size_t i = v0; i < v1; ++i) {
      const Vec3& p = mesh.positions[i];
      const Vec3& nn = mesh.normals[i];
      const float* m = xf.position;
      const float* q = xf.normal;
      eye_p[i] = Vec3(m[0] * p.x() + m[1] * p.y() + m[2] * p.z() + m[3], m[4] * p.x() + m[5] * p.y() + m[6] * p.z() + m[7],
                      m[8] * p.x() + m[9] * p.y() + m[10] * p.z() + m[11]);
      eye_n[i] = Vec3(q[0] * nn.x() + q[1] * nn.y() + q[2] * nn.z(), q[3] * nn.x() + q[4] * nn.y() + q[5] * nn.z(),
                      q[6] * nn.x() + q[7] * nn.y() + q[8] * nn.z());
    }
    // Tangents are directions on the surface: the model-view's linear part moves them (normals take
    // its inverse transpose). A mirror reverses cross(n, t) against the moved bitangent: w flips.
    if (draw.layout.has(raster::Varying::tangent)) {
      os.eye_t.resize(n);
      os.tangent_sign.resize(n);
      const float* m = xf.position;
      const float flip = os.mirrored ? -1.0f : 1.0f;
      for (std::size_t i = v0; i < v1; ++i) {
        const Vec4& t = mesh.tangents[i];
        os.eye_t[i] = Vec3(m[0] * t.x() + m[1] * t.y() + m[2] * t.z(), m[4] * t.x() + m[5] * t.y() + m[6] * t.z(),
                           m[8] * t.x() + m[9] * t.y() + m[10] * t.z());
        os.tangent_sign[i] = flip * t.w();
      }
    }
  }
  for (std::size_t g = 0; g < raster::kGeneratedVaryings.size(); ++g) {
    const raster::Varying v = raster::kGeneratedVaryings[g];
    if (!draw.layout.has(v)) continue;
    const auto w = static_cast<std::size_t>(raster::width_of(v));
    os.generated[g].resize(n * w);
    for (std::size_t i = v0; i < v1; ++i) {
      const float p[3] = {eye_p[i].x(), eye_p[i].y(), eye_p[i].z()}, nn[3] = {eye_n[i].x(), eye_n[i].y(), eye_n[i].z()};
      pixel::generate_at_vertex(draw, v, p, nn, os.generated[g].data() + i * w);
    }
  }
  if (shading == ShadingMode::gouraud) {
    front.resize(n);
    if (two_sided) back.resize(n);
    if (split) {
      os.front_spec.resize(n);
      if (two_sided) os.back_spec.resize(n);
    }
    // Per-vertex relief: the normals the maps perturb, for the vertices lit.
    const Material& m = scene.materials[unit.material];
    const bool relief = vertex_relief && !kind.plain() && (m.normal_texture != kNoTexture || m.bump_texture != kNoTexture) &&
                        !lf.color_material && mesh.tangents.size() == n && mesh.uvs.size() == n && n > 0;
    frame::VertexRelief vr;
    if (relief) {
      vr.uv_scale[0] = m.uv_scale.x(), vr.uv_scale[1] = m.uv_scale.y();
      if (m.normal_texture != kNoTexture) {
        vr.normal_map = &samplers.as_made[static_cast<std::size_t>(m.normal_texture)];
        vr.normal_scale = m.normal_scale;
      }
      if (m.bump_texture != kNoTexture) {
        vr.bump_map = &samplers.as_made[static_cast<std::size_t>(m.bump_texture)];
        vr.bump_scale = m.bump_scale;
        vr.bump_du = 1.0f / vr.bump_map->lod_width, vr.bump_dv = 1.0f / vr.bump_map->lod_height;
      }
      vr.lod = frame::vertex_relief_lod(mesh, vr.normal_map ? *vr.normal_map : *vr.bump_map, vr.uv_scale);
      os.relief_normals.resize(n);
    }
    const Vec3* normals = relief ? os.relief_normals.data() : nullptr;
    // Only the vertices of triangles that may be drawn are lit (the others' colours are never
    // read): the first phase of assembly places the triangles without their varyings and marks
    // their vertices (raster::place_range, ranges in parallel), then they are listed per vertex
    // chunk. A vertex's colour does not depend on its batch or its neighbours, so the image is
    // the same as with every vertex lit; assemble_object() finishes the placed triangles.
    const std::uint32_t* index = nullptr;
    std::atomic<std::size_t> listed{0};  // vertices lit
    if (!light_every_vertex) {
      std::vector<std::uint8_t>& drawn = os.drawn;
      drawn.resize(n);
      os.lit_index.resize(n);
      std::fill(drawn.begin() + static_cast<std::ptrdiff_t>(v0), drawn.begin() + static_cast<std::ptrdiff_t>(v1), 0);
      place_object(mesh, object, os, drawn.data(), slot);
      index = os.lit_index.data();
    }
    // Chunks of exactly kVertexChunk vertices from v0 (a task takes whole chunks), so that which
    // way each is lit, and so the counts, is the same for any thread count.
    auto light_chunk = [&](std::size_t begin, std::size_t end, int chunk_slot) {
      lighting::SoaScratch& soa = worker(chunk_slot).soa;
      const std::uint32_t* chunk_index = index;
      if (index) {
        std::uint32_t drawn = 0;  // the flags are 0 or 1 (a sum the compiler vectorises)
        for (std::size_t v = begin; v != end; ++v) drawn += os.drawn[v];
        // Most of the chunk drawn: every vertex of it is lit where it lies, which costs less than
        // copying the drawn ones out through the list and back (frame::kLightWholeChunk).
        if (drawn * frame::kLightWholeChunk.denominator > (end - begin) * frame::kLightWholeChunk.numerator) {
          chunk_index = nullptr;
        } else {  // the drawn vertices, listed from the chunk's own offset
          std::uint32_t* list = os.lit_index.data() + begin;
          std::size_t count = 0;
          for (std::size_t v = begin; v != end; ++v) {
            list[count] = static_cast<std::uint32_t>(v);
            count += os.drawn[v];
          }
          end = begin + count;
        }
      }
      listed.fetch_add(end - begin, std::memory_order_relaxed);
      if (relief) {
        for (std::size_t k = begin; k != end; ++k) {
          const std::size_t v = chunk_index ? chunk_index[k] : k;
          os.relief_normals[v] = frame::vertex_relief_normal(vr, mesh, v);
        }
      }
      shader.light_mesh(mesh, view, inst.model, false, begin, end, front.data(), soa,
                        split ? os.front_spec.data() : nullptr, chunk_index, normals);
      if (two_sided) {
        shader.light_mesh(mesh, view, inst.model, true, begin, end, back.data(), soa,
                          split ? os.back_spec.data() : nullptr, chunk_index, normals);
      }
    };
    for_chunks(0, (v1 - v0 + kVertexChunk - 1) / kVertexChunk, 1, slot,
               [&](const tbb::blocked_range<std::size_t>& r, int chunk_slot) {
                 for (std::size_t c = r.begin(); c != r.end(); ++c) {
                   light_chunk(v0 + c * kVertexChunk, std::min(v1, v0 + (c + 1) * kVertexChunk), chunk_slot);
                 }
               });
    const std::size_t lit_vertices = listed.load(std::memory_order_relaxed);
    counts.vertices_skipped += (v1 - v0 - lit_vertices) * (two_sided ? 2 : 1);
    count_pairs(lit_vertices * (two_sided ? 2 : 1));
    counts.seconds_lighting += seconds_since(lighting_start);
    return;
  }

  if (shading == ShadingMode::flat) {
    // One evaluation per triangle: the face normal (from the eye-space corners) at the centroid.
    const std::size_t t_count = mesh.triangle_count(), t0 = unit.first_triangle, t1 = unit.end_triangle;
    centroid.resize(t_count);
    face_normal.resize(t_count);
    for (std::size_t t = t0; t < t1; ++t) {
      const auto& tri = mesh.triangles[t];
      const Vec3 &a = eye_p[tri[0]], &b = eye_p[tri[1]], &c = eye_p[tri[2]];
      centroid[t] = (a + b + c) / 3.0f;
      face_normal[t] = os.mirrored ? (c - a).cross(b - a) : (b - a).cross(c - a);
    }
    if (lf.color_material) {  // the albedo at the centroid: the mean of the corners' colours
      os.flat_albedo.resize(t_count);
      for (std::size_t t = t0; t < t1; ++t) {
        const auto& tri = mesh.triangles[t];
        os.flat_albedo[t] = (mesh.colors[tri[0]] + mesh.colors[tri[1]] + mesh.colors[tri[2]]) / 3.0f;
      }
    }
    front.resize(t_count);
    if (two_sided) back.resize(t_count);
    if (split) {
      os.front_spec.resize(t_count);
      if (two_sided) os.back_spec.resize(t_count);
    }
    // Only triangles that may be drawn are lit (unless light_every_vertex): the first phase of
    // assembly lists them per range (raster::place_range); per range their centroids, normals
    // and albedos are moved to the front of the range's part of the arrays, lit there, and each
    // colour moved back to its triangle, last first (triangle t_k >= slot k, so no colour is
    // overwritten before it is moved). A point's colour does not depend on its place in a batch,
    // so the colours are those of lighting every triangle.
    if (!light_every_vertex) place_object(mesh, object, os, nullptr, slot);
    std::atomic<std::size_t> listed{0};
    const std::size_t first = first_range[object];
    // Triangles [begin, end): lit whole, or (a set-up range) only those the first phase listed.
    auto light = [&](std::size_t begin, std::size_t end, const raster::PendingTriangles* pending, int chunk_slot) {
      std::size_t count = end - begin;
      const std::uint32_t* list = nullptr;
      if (pending) {
        list = pending->triangle.data();
        count = pending->triangle.size();
        for (std::size_t k = 0; k < count; ++k) {
          const std::size_t t = list[k];
          centroid[begin + k] = centroid[t], face_normal[begin + k] = face_normal[t];
          if (lf.color_material) os.flat_albedo[begin + k] = os.flat_albedo[t];
        }
      }
      listed.fetch_add(count, std::memory_order_relaxed);
      auto shade = [&](std::vector<Color3>& out, std::vector<Color3>& spec) {
        shader.shade_points(count, centroid.data() + begin, face_normal.data() + begin, out.data() + begin,
                            worker(chunk_slot).soa, lf.color_material ? os.flat_albedo.data() + begin : nullptr,
                            split ? spec.data() + begin : nullptr);
        if (!list) return;
        for (std::size_t k = count; k-- > 0;) {
          out[list[k]] = out[begin + k];
          if (split) spec[list[k]] = spec[begin + k];
        }
      };
      shade(front, os.front_spec);
      if (two_sided) {
        for (std::size_t k = begin; k != begin + count; ++k) face_normal[k] = -face_normal[k];
        shade(back, os.back_spec);
      }
    };
    if (light_every_vertex) {
      for_chunks(t0, t1, kVertexChunk, slot, [&](const tbb::blocked_range<std::size_t>& r, int chunk_slot) {
        light(r.begin(), r.end(), nullptr, chunk_slot);
      });
    } else {
      for_chunks(0, unit.ranges(), 1, slot, [&](const tbb::blocked_range<std::size_t>& rs, int chunk_slot) {
        for (std::size_t r = rs.begin(); r != rs.end(); ++r) {
          const std::size_t begin = t0 + r * kTriangleRange;
          light(begin, std::min(t1, begin + kTriangleRange), &range_pending[first + r], chunk_slot);
        }
      });
    }
    const std::size_t lit_triangles = listed.load(std::memory_order_relaxed);
    counts.vertices_skipped += (t1 - t0 - lit_triangles) * (two_sided ? 2 : 1);
    count_pairs(lit_triangles * (two_sided ? 2 : 1));
  }
  counts.seconds_lighting += seconds_since(lighting_start);
}

void Renderer::Impl::place_object(const Mesh& mesh, std::uint32_t object, const ObjectScratch& os, std::uint8_t* drawn,
                                  int slot) {
  raster::ObjectVertices placing;  // what the first phase reads: positions and winding
  placing.clip = os.clip;
  placing.screen = os.screen;
  placing.mirrored = os.mirrored;
  placing.two_sided = draws.two_sided[object] != 0;
  placing.object = object;
  const std::size_t first = first_range[object];
  const DrawUnit& unit = units[object];
  placing.only = unit.only;
  for_chunks(0, unit.ranges(), 1, slot, [&](const tbb::blocked_range<std::size_t>& rs, int) {
    for (std::size_t r = rs.begin(); r != rs.end(); ++r) {
      const std::size_t begin = unit.first_triangle + r * kTriangleRange;
      raster::place_range(pass->assembly, mesh, placing, begin, std::min(unit.end_triangle, begin + kTriangleRange),
                          range_triangles[first + r], range_binning[first + r], range_pending[first + r], drawn);
    }
  });
}

void Renderer::Impl::assemble_object(const Mesh& mesh, std::uint32_t object, float alpha, const ObjectScratch& os,
                                     int slot) {
  const bool two_sided = draws.two_sided[object] != 0;
  const std::size_t first = first_range[object];
  const bool flat = pass->shading == ShadingMode::flat;
  raster::ObjectVertices vertices;
  const pixel::Draw& draw = draws.programs[object];
  const lighting::LightingFeatures& lf = draws.features[object];
  vertices.layout = draw.layout;
  vertices.clip = os.clip;
  vertices.screen = os.screen;
  using raster::Varying;
  // Vec3 and Color3 are three packed floats (types.hpp); an empty array (a mesh without vertices) is null.
  auto source = [&](Varying v, const auto& values) {
    vertices.varying[static_cast<int>(v)] = draw.layout.has(v) ? reinterpret_cast<const float*>(values.data()) : nullptr;
  };
  source(Varying::front_color, os.front);
  source(Varying::back_color, os.back);
  source(Varying::front_secondary, os.front_spec);
  source(Varying::back_secondary, os.back_spec);
  source(Varying::eye_position, os.eye_p);
  source(Varying::normal, os.eye_n);
  source(Varying::albedo, mesh.colors);
  source(Varying::uv, mesh.uvs);
  source(Varying::lightmap_uv, mesh.lightmap_uvs);
  source(Varying::tangent, os.eye_t);
  source(Varying::tangent_sign, os.tangent_sign);
  for (std::size_t g = 0; g < raster::kGeneratedVaryings.size(); ++g) source(raster::kGeneratedVaryings[g], os.generated[g]);
  vertices.flat_front = flat ? os.front.data() : nullptr;
  vertices.flat_back = flat && two_sided ? os.back.data() : nullptr;
  vertices.flat_secondary_front = flat && lf.separate_specular ? os.front_spec.data() : nullptr;
  vertices.flat_secondary_back = flat && two_sided && lf.separate_specular ? os.back_spec.data() : nullptr;
  vertices.mirrored = os.mirrored;
  vertices.two_sided = two_sided;
  vertices.only = units[object].only;
  vertices.object = object;
  vertices.alpha = alpha;
  // Gouraud and flat lit only where drawn: the second phase of the assembly prepare_object() began.
  const bool placed = !pass->depth_only && pass->shading != ShadingMode::phong && !light_every_vertex;
  const DrawUnit& unit = units[object];
  for_chunks(0, unit.ranges(), 1, slot, [&](const tbb::blocked_range<std::size_t>& rs, int) {
    for (std::size_t r = rs.begin(); r != rs.end(); ++r) {
      if (placed) {
        raster::finish_range(pass->assembly, mesh, vertices, range_triangles[first + r], range_binning[first + r],
                             range_pending[first + r]);
        continue;
      }
      const std::size_t begin = unit.first_triangle + r * kTriangleRange;
      raster::assemble_range(pass->assembly, mesh, vertices, begin, std::min(unit.end_triangle, begin + kTriangleRange),
                             range_triangles[first + r], range_binning[first + r], range_pending[first + r]);
    }
  });
}

}  // namespace facet
