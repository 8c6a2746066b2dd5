/* The C API, from C: build a scene from arrays, render into a caller buffer with guard bytes,
 * and check that bad arguments are refused with a message, before any byte is written. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "facet/facet.h"

#include "check.h"

enum { W = 48, H = 32, GUARD = 64 };

/* A resolver serving one OBJ from memory under the name "mem/tri.obj". */
static const char kTriangle[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
static int resolver_calls = 0;
static int resolve_from_memory(void* user, const char* name, const void** bytes, size_t* size) {
  (void)user;
  ++resolver_calls;
  if (strcmp(name, "mem/tri.obj") != 0) return 1;
  *bytes = kTriangle;
  *size = sizeof kTriangle - 1;
  return 0;
}

static int progress_calls = 0;
static int cancel_at_first_call(void* user, double done) {
  (void)user;
  ++progress_calls;
  return done < 0.0; /* 0: cancel */
}

/* A scene of one triangle (three xyz positions) in an emissive white material of `alpha`, with
 * alpha to coverage when `coverage` is non-zero. */
static facet_scene* white_triangle(const float tri[9], float alpha, int coverage) {
  facet_scene* s = facet_scene_create();
  const uint32_t idx[] = {0, 1, 2};
  uint32_t m = 0, mat = 0;
  CHECK(facet_scene_add_mesh(s, tri, 3, NULL, idx, 1, &m) == FACET_OK);
  facet_material white = facet_material_default();
  const float one[3] = {1, 1, 1}, zero[3] = {0, 0, 0};
  memcpy(white.emissive, one, sizeof one);
  memcpy(white.ambient, zero, sizeof zero);
  memcpy(white.diffuse, zero, sizeof zero);
  memcpy(white.specular, zero, sizeof zero);
  white.alpha = alpha;
  white.alpha_to_coverage = coverage;
  CHECK(facet_scene_add_material(s, &white, &mat) == FACET_OK);
  CHECK(facet_scene_add_object(s, m, mat, NULL, NULL) == FACET_OK);
  return s;
}

/* `scene` into a size x size RGBA8 image with `samples` per pixel, nothing culled. */
static void render_samples(const facet_scene* scene, int samples, unsigned char* px, int size) {
  facet_render_config rc = facet_render_config_default();
  rc.samples = samples;
  rc.cull = FACET_CULL_NONE;
  rc.srgb = 0; /* GL's framebuffer: the linear values */
  facet_renderer* r = facet_renderer_create(&rc, NULL);
  CHECK(r != NULL);
  CHECK(facet_render(r, scene, px, size, size, (size_t)size * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
  facet_renderer_destroy(r);
}

int main(void) {
  /* An octahedron of radius 1 at the origin, normals computed by facet. */
  const float positions[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  const uint32_t indices[] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  facet_scene* scene = facet_scene_create();
  CHECK(scene != NULL);
  uint32_t mesh = 99, material = 99, object = 99;
  CHECK(facet_scene_add_mesh(scene, positions, 6, NULL, indices, 8, &mesh) == FACET_OK);
  CHECK(mesh == 0);
  facet_material m = facet_material_default();
  m.diffuse[0] = 0.9f, m.diffuse[1] = 0.4f, m.diffuse[2] = 0.1f;
  CHECK(facet_scene_add_material(scene, &m, &material) == FACET_OK);
  CHECK(facet_scene_add_object(scene, mesh, material, NULL, &object) == FACET_OK);
  facet_light light = facet_light_default();
  CHECK(facet_scene_add_light(scene, &light, NULL) == FACET_OK);
  facet_camera camera = facet_camera_default();
  camera.eye[2] = 4.0f;
  CHECK(facet_scene_set_camera(scene, &camera) == FACET_OK);
  CHECK(strcmp(facet_scene_last_error(scene), "") == 0);

  /* Bad arguments: refused, with the argument named; the scene is unchanged. */
  CHECK(facet_scene_add_object(scene, 7, material, NULL, NULL) == FACET_INVALID_ARGUMENT);
  CHECK(strstr(facet_scene_last_error(scene), "mesh_id") != NULL);
  const uint32_t bad_indices[] = {0, 1, 9};
  CHECK(facet_scene_add_mesh(scene, positions, 6, NULL, bad_indices, 1, NULL) == FACET_INVALID_ARGUMENT);
  CHECK(strlen(facet_scene_last_error(scene)) > 0);
  facet_material bad = m;
  bad.shininess = NAN;
  CHECK(facet_scene_add_material(scene, &bad, NULL) == FACET_INVALID_ARGUMENT);
  CHECK(strstr(facet_scene_last_error(scene), "shininess") != NULL);
  camera.near_plane = -1.0f;
  CHECK(facet_scene_set_camera(scene, &camera) == FACET_INVALID_ARGUMENT);
  CHECK(strstr(facet_scene_last_error(scene), "camera.near") != NULL);

  facet_render_config config = facet_render_config_default();
  config.threads = 2;
  config.clear_color[0] = 0.0f, config.clear_color[1] = 0.0f, config.clear_color[2] = 1.0f;
  facet_status status = FACET_IO_ERROR;
  facet_renderer* renderer = facet_renderer_create(&config, &status);
  CHECK(renderer != NULL && status == FACET_OK);

  static unsigned char buffer[GUARD + W * H * 4 + GUARD];
  memset(buffer, 0xA5, sizeof buffer);
  unsigned char* pixels = buffer + GUARD;

  /* Invalid views: an error, and not a byte written. */
  CHECK(facet_render(renderer, scene, pixels, W, H, W * 4 - 1, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_INVALID_ARGUMENT);
  CHECK(strlen(facet_renderer_last_error(renderer)) > 0);
  CHECK(facet_render(renderer, scene, pixels, 0, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_INVALID_ARGUMENT);
  CHECK(facet_render(renderer, NULL, pixels, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_INVALID_ARGUMENT);
  CHECK(facet_render(renderer, scene, pixels, W, H, W * 4, (facet_pixel_format)7, 0, NULL, 0, NULL) ==
        FACET_INVALID_ARGUMENT);
  for (size_t i = 0; i < sizeof buffer; ++i) CHECK(buffer[i] == 0xA5);

  facet_frame_stats stats = {0};
  memset(&stats, 0, sizeof stats);
  static float depth[W * H];
  CHECK(facet_render(renderer, scene, pixels, W, H, W * 4, FACET_RGBA8, 0, depth, W * sizeof(float), &stats) == FACET_OK);
  CHECK(strcmp(facet_renderer_last_error(renderer), "") == 0);
  CHECK(stats.triangles_in == 8 && stats.triangles_drawn >= 4 && stats.pixels_filled > 0 && stats.threads == 2);
  /* The centre is the lit octahedron (reddish), the corner is the clear colour (blue). */
  const unsigned char* centre = pixels + 4 * (W * (H / 2) + W / 2);
  CHECK(centre[0] > centre[2] && centre[3] == 255);
  CHECK(pixels[0] == 0 && pixels[1] == 0 && pixels[2] == 255 && pixels[3] == 255);
  CHECK(depth[W * (H / 2) + W / 2] < 1.0f && depth[0] == 1.0f);
  for (size_t i = 0; i < GUARD; ++i) CHECK(buffer[i] == 0xA5 && buffer[sizeof buffer - 1 - i] == 0xA5);
  /* Every triangle is accounted for; the closed octahedron's back half is culled, and the
   * vertices only back faces use are not lit. */
  CHECK(stats.triangles_in == stats.triangles_drawn + stats.triangles_culled + stats.triangles_outside +
                                  stats.triangles_degenerate + stats.triangles_small + stats.triangles_nonfinite);
  CHECK(stats.triangles_culled == 4 && stats.bin_entries >= stats.triangles_drawn);
  CHECK(stats.pixels_tested >= stats.pixels_filled && stats.vertex_lights_evaluated >= stats.vertices_lit);
  CHECK(stats.seconds_lighting >= 0.0 && stats.seconds_geometry >= 0.0 && stats.seconds_raster > 0.0 &&
        stats.seconds_resolve >= 0.0 && stats.seconds_total >= stats.seconds_raster);
  /* facet computed the normals per face, so each triangle has its own three vertices: the four
   * culled faces' twelve are not lit. */
  CHECK(stats.vertices_lit == 12 && stats.vertices_skipped == 12);

  /* Lighting every vertex: the same bytes, nothing skipped. */
  {
    static unsigned char first[W * H * 4];
    memcpy(first, pixels, sizeof first);
    facet_render_config every = config;
    every.light_every_vertex = 1;
    facet_renderer* r2 = facet_renderer_create(&every, &status);
    CHECK(r2 != NULL && status == FACET_OK);
    facet_frame_stats s2 = {0};
    memset(&s2, 0xFF, sizeof s2);
    CHECK(facet_render(r2, scene, pixels, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, &s2) == FACET_OK);
    CHECK(memcmp(first, pixels, sizeof first) == 0);
    CHECK(s2.vertices_skipped == 0 && s2.vertices_lit == 24);
    facet_renderer_destroy(r2);
  }

  /* A memory budget the frame exceeds: out of memory, before a byte is written. */
  memset(buffer, 0xA5, sizeof buffer);
  config = facet_render_config_default();
  config.memory_budget_bytes = 1024;
  facet_renderer* tight = facet_renderer_create(&config, &status);
  CHECK(tight != NULL);
  CHECK(facet_render(tight, scene, pixels, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OUT_OF_MEMORY);
  CHECK(strstr(facet_renderer_last_error(tight), "memory_budget_bytes") != NULL);
  for (size_t i = 0; i < sizeof buffer; ++i) CHECK(buffer[i] == 0xA5);
  facet_renderer_destroy(tight);
  /* A progress callback that cancels: FACET_CANCELLED. */
  config = facet_render_config_default();
  config.progress = cancel_at_first_call;
  facet_renderer* cancelled = facet_renderer_create(&config, &status);
  CHECK(cancelled != NULL);
  CHECK(facet_render(cancelled, scene, pixels, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_CANCELLED);
  CHECK(progress_calls == 1);
  facet_renderer_destroy(cancelled);

  /* Invalid configurations are refused at creation, also enum values no enumerator has. */
  config = facet_render_config_default();
  config.tile_size = 12;
  CHECK(facet_renderer_create(&config, &status) == NULL && status == FACET_INVALID_ARGUMENT);
  config = facet_render_config_default();
  config.shading = (facet_shading)9;
  CHECK(facet_renderer_create(&config, &status) == NULL && status == FACET_INVALID_ARGUMENT);
  config = facet_render_config_default();
  CHECK(config.pow_tier == FACET_POW_AUTO && config.cull_lights == 1 && config.light_every_vertex == 0 && config.hdr == 0 &&
        config.vertex_relief == 0 && config.pixel_precision == FACET_PIXELS_AUTO);
  config.pixel_precision = (facet_pixel_precision)3;
  {
    facet_status st = FACET_OK;
    CHECK(facet_renderer_create(&config, &st) == NULL && st == FACET_INVALID_ARGUMENT);
  }
  config.pixel_precision = FACET_PIXELS_EXACT;
  {
    facet_renderer* exact = facet_renderer_create(&config, &status);
    CHECK(exact != NULL && status == FACET_OK);
    facet_renderer_destroy(exact);
  }
  /* Multisampling: 1 by default; 3 samples are refused; 4 soften a triangle's slanted edge (some
   * pixel between the clear colour and the triangle's), where 1 sample leaves only the two. */
  CHECK(config.samples == 1);
  config.samples = 3;
  CHECK(facet_renderer_create(&config, &status) == NULL && status == FACET_INVALID_ARGUMENT);
  {
    const float tri[] = {-5, -4, -3, 5, -3, -3, -1, 5, -3};
    facet_scene* s = white_triangle(tri, 1.0f, 0);
    unsigned char one_sample[16 * 16 * 4], four[16 * 16 * 4];
    int between_1 = 0, between_4 = 0;
    for (int samples = 1; samples <= 4; samples += 3) {
      unsigned char* px = samples == 1 ? one_sample : four;
      render_samples(s, samples, px, 16);
      for (int i = 0; i < 16 * 16; ++i) {
        if (px[4 * i] > 0 && px[4 * i] < 255) *(samples == 1 ? &between_1 : &between_4) += 1;
      }
    }
    CHECK(between_1 == 0 && between_4 > 4);
    facet_scene_destroy(s);
  }
  /* Alpha to coverage: off by default; a white triangle over the whole image at alpha 0.5 covers
   * 2 of 4 samples (half white), and at 1 sample every pixel (GL ignores it there). */
  {
    CHECK(facet_material_default().alpha_to_coverage == 0);
    const float tri[] = {-50, -50, -3, 50, -50, -3, 0, 50, -3};
    facet_scene* s = white_triangle(tri, 0.5f, 1);
    for (int samples = 1; samples <= 4; samples += 3) {
      unsigned char px[8 * 8 * 4];
      render_samples(s, samples, px, 8);
      CHECK(samples == 1 ? px[4 * 27] == 255 : (px[4 * 27] >= 127 && px[4 * 27] <= 128));
    }
    facet_scene_destroy(s);
  }
  config.samples = 1;
  config.pow_tier = (facet_pow_tier)5;
  CHECK(facet_renderer_create(&config, &status) == NULL && status == FACET_INVALID_ARGUMENT);
  config.pow_tier = FACET_POW_SCHLICK;
  {
    facet_renderer* schlick = facet_renderer_create(&config, &status);
    CHECK(schlick != NULL && status == FACET_OK);
    facet_renderer_destroy(schlick);
  }
  /* Per-vertex relief: a quad under a one-texel normal map tilted towards +x, lit from +x; Gouraud
   * ignores the map unless vertex_relief is set, then the quad is brighter. */
  {
    facet_scene* s = facet_scene_create();
    const float quad[] = {-5, -5, -3, 5, -5, -3, 5, 5, -3, -5, 5, -3};
    const uint32_t tris[] = {0, 1, 2, 0, 2, 3};
    const float uvs[] = {0, 0, 1, 0, 1, 1, 0, 1};
    const unsigned char tilted[4] = {220, 128, 200, 255};
    uint32_t q = 0, tex = 0, mat = 0;
    CHECK(facet_scene_add_mesh(s, quad, 4, NULL, tris, 2, &q) == FACET_OK);
    CHECK(facet_scene_set_mesh_uvs(s, q, uvs) == FACET_OK);
    CHECK(facet_scene_generate_tangents(s, q) == FACET_OK);
    CHECK(facet_scene_add_texture_rgba8(s, tilted, 1, 1, FACET_NEAREST, FACET_WRAP_REPEAT, &tex) == FACET_OK);
    facet_material bumpy = facet_material_default();
    bumpy.normal_texture = (int32_t)tex;
    CHECK(facet_scene_add_material(s, &bumpy, &mat) == FACET_OK);
    CHECK(facet_scene_add_object(s, q, mat, NULL, NULL) == FACET_OK);
    facet_light from_x = facet_light_default();
    from_x.direction[0] = -1, from_x.direction[1] = 0, from_x.direction[2] = -0.3f;
    CHECK(facet_scene_add_light(s, &from_x, NULL) == FACET_OK);
    facet_camera cam = facet_camera_default();
    cam.eye[0] = cam.eye[1] = cam.eye[2] = 0;
    cam.target[0] = 0, cam.target[1] = 0, cam.target[2] = -1;
    CHECK(facet_scene_set_camera(s, &cam) == FACET_OK);
    static unsigned char plain[8 * 8 * 4], relief[8 * 8 * 4];
    facet_render_config rc = facet_render_config_default();
    facet_renderer* r = facet_renderer_create(&rc, NULL);
    CHECK(facet_render(r, s, plain, 8, 8, 8 * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    facet_renderer_destroy(r);
    rc.vertex_relief = 1;
    r = facet_renderer_create(&rc, NULL);
    CHECK(facet_render(r, s, relief, 8, 8, 8 * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    facet_renderer_destroy(r);
    CHECK(relief[4 * 36] > plain[4 * 36] + 20);
    facet_scene_destroy(s);
  }
  light.type = (facet_light_type)-3;
  CHECK(facet_scene_add_light(scene, &light, NULL) == FACET_INVALID_ARGUMENT);
  CHECK(strstr(facet_scene_last_error(scene), "light.type") != NULL);

  /* Surfaces: a quad with texture coordinates under a one-texel texture (GL_MODULATE of the
   * emissive colour), alpha-blended over the clear colour, then fog. */
  {
    facet_scene* s = facet_scene_create();
    const float quad[] = {-5, -5, -3, 5, -5, -3, 5, 5, -3, -5, 5, -3};
    const uint32_t tris[] = {0, 1, 2, 0, 2, 3};
    const float uvs[] = {0, 0, 1, 0, 1, 1, 0, 1};
    const float bad_uvs[] = {0, 0, 1, 0, 1, 1, 0, NAN};
    const unsigned char texel[4] = {255, 128, 0, 255};
    uint32_t q = 9, tex = 9, mat = 9;
    CHECK(facet_scene_add_mesh(s, quad, 4, NULL, tris, 2, &q) == FACET_OK);
    CHECK(facet_scene_set_mesh_uvs(s, q, bad_uvs) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "uvs") != NULL);
    CHECK(facet_scene_set_mesh_uvs(s, q, uvs) == FACET_OK);
    CHECK(facet_scene_add_texture_rgba8(s, texel, 1, 1, FACET_BILINEAR, FACET_WRAP_REPEAT, &tex) == FACET_OK && tex == 0);
    CHECK(facet_scene_add_texture_rgba8(s, texel, 0, 1, FACET_BILINEAR, FACET_WRAP_REPEAT, NULL) == FACET_INVALID_ARGUMENT);
    /* Encoding: caller texels start linear; sRGB and back; unknown values and ids are refused. */
    facet_texture_encoding enc = FACET_ENCODING_SRGB;
    CHECK(facet_scene_texture_encoding(s, tex, &enc) == FACET_OK && enc == FACET_ENCODING_LINEAR);
    CHECK(facet_scene_set_texture_encoding(s, tex, FACET_ENCODING_SRGB) == FACET_OK);
    CHECK(facet_scene_texture_encoding(s, tex, &enc) == FACET_OK && enc == FACET_ENCODING_SRGB);
    CHECK(facet_scene_set_texture_encoding(s, tex, (facet_texture_encoding)7) == FACET_INVALID_ARGUMENT);
    CHECK(facet_scene_set_texture_encoding(s, 99, FACET_ENCODING_SRGB) == FACET_INVALID_ARGUMENT);
    CHECK(facet_scene_texture_encoding(s, 99, &enc) == FACET_INVALID_ARGUMENT);
    CHECK(facet_scene_set_texture_encoding(s, tex, FACET_ENCODING_LINEAR) == FACET_OK);
    /* Tangents: given (w must be +-1) or generated from the uvs; a normal map needs them. */
    {
      const float tangents[] = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
      const float bad_tangents[] = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 0.5f, 1, 0, 0, 1};
      CHECK(facet_scene_set_mesh_tangents(s, q, bad_tangents) == FACET_INVALID_ARGUMENT);
      CHECK(strstr(facet_scene_last_error(s), "tangents[2]") != NULL);
      CHECK(facet_scene_set_mesh_tangents(s, q, tangents) == FACET_OK);
      CHECK(facet_scene_set_mesh_tangents(s, q, NULL) == FACET_OK);
      CHECK(facet_scene_generate_tangents(s, q) == FACET_OK);
      CHECK(facet_scene_generate_tangents(s, 77) == FACET_INVALID_ARGUMENT);
      facet_material bumpy = facet_material_default();
      CHECK(bumpy.normal_texture == -1 && bumpy.normal_scale == 1.0f);
      bumpy.normal_texture = (int32_t)tex;
      bumpy.normal_scale = INFINITY;
      CHECK(facet_scene_add_material(s, &bumpy, NULL) == FACET_INVALID_ARGUMENT);
      CHECK(strstr(facet_scene_last_error(s), "normal_scale") != NULL);
    }
    CHECK(facet_scene_load_texture(s, "/nonexistent/t.png", FACET_TRILINEAR, FACET_WRAP_CLAMP, NULL) == FACET_IO_ERROR);
    CHECK(strstr(facet_scene_last_error(s), "t.png") != NULL);
    facet_material sm = facet_material_default();
    sm.ambient[0] = sm.ambient[1] = sm.ambient[2] = 0;
    sm.diffuse[0] = sm.diffuse[1] = sm.diffuse[2] = 0;
    sm.emissive[0] = sm.emissive[1] = sm.emissive[2] = 1;
    sm.diffuse_texture = 5;
    CHECK(facet_scene_add_material(s, &sm, NULL) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "diffuse_texture") != NULL);
    sm.diffuse_texture = (int32_t)tex;
    sm.uv_scale[0] = 0;
    CHECK(facet_scene_add_material(s, &sm, NULL) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "uv_scale") != NULL);
    sm.uv_scale[0] = 1;
    sm.blend = FACET_BLEND_ALPHA;
    sm.alpha = 0.5f;
    CHECK(facet_scene_add_material(s, &sm, &mat) == FACET_OK);
    CHECK(facet_scene_add_object(s, q, mat, NULL, NULL) == FACET_OK);
    facet_camera cam = facet_camera_default();
    cam.eye[0] = cam.eye[1] = cam.eye[2] = 0;
    cam.target[0] = 0, cam.target[1] = 0, cam.target[2] = -1;
    cam.vertical_fov_deg = 90;
    CHECK(facet_scene_set_camera(s, &cam) == FACET_OK);
    facet_render_config sc = facet_render_config_default();
    CHECK(sc.srgb == 1); /* 8-bit output is sRGB-encoded by default */
    sc.srgb = 0;         /* the values below are GL's linear framebuffer's */
    sc.clear_color[0] = 0, sc.clear_color[1] = 0, sc.clear_color[2] = 1, sc.clear_color[3] = 1;
    facet_renderer* sr = facet_renderer_create(&sc, &status);
    CHECK(sr != NULL);
    static unsigned char img[16 * 16 * 4];
    CHECK(facet_render(sr, s, img, 16, 16, 16 * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    const unsigned char* c = img + 4 * (16 * 8 + 8);
    /* (1, 128/255, 0) at alpha 0.5 over (0, 0, 1): (128, 64, 128) within a step. */
    CHECK(abs(c[0] - 128) <= 1 && abs(c[1] - 64) <= 1 && abs(c[2] - 128) <= 1);
    facet_fog fog = facet_fog_default();
    CHECK(fog.mode == FACET_FOG_NONE);
    fog.mode = FACET_FOG_LINEAR;
    fog.start = 5, fog.end = 4;
    CHECK(facet_scene_set_fog(s, &fog) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "fog.end") != NULL);
    fog.start = 0, fog.end = 6; /* depth 3: f = 0.5; fog colour black */
    CHECK(facet_scene_set_fog(s, &fog) == FACET_OK);
    CHECK(facet_render(sr, s, img, 16, 16, 16 * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    /* (0.5, 64/255, 0) at alpha 0.5 over (0, 0, 1): (64, 32, 128). */
    CHECK(abs(c[0] - 64) <= 1 && abs(c[1] - 32) <= 1 && abs(c[2] - 128) <= 1);
    /* Emission after texturing: emissive x the emissive texture's texel, no fog, opaque. */
    CHECK(sm.emissive_texture == -1 && sm.emission_after_texture == 0);
    sm.emissive_texture = 7;
    CHECK(facet_scene_set_material(s, mat, &sm) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "emissive_texture") != NULL);
    sm.emissive_texture = (int32_t)tex;
    sm.diffuse_texture = -1;
    sm.emissive[0] = sm.emissive[1] = sm.emissive[2] = 0.5f;
    sm.blend = FACET_BLEND_OPAQUE;
    sm.alpha = 1;
    CHECK(facet_scene_set_material(s, mat, &sm) == FACET_OK);
    fog.mode = FACET_FOG_NONE;
    CHECK(facet_scene_set_fog(s, &fog) == FACET_OK);
    CHECK(facet_render(sr, s, img, 16, 16, 16 * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    /* 0.5 x (1, 128/255, 0): (128, 64, 0), opaque. */
    CHECK(abs(c[0] - 128) <= 1 && abs(c[1] - 64) <= 1 && c[2] == 0 && c[3] == 255);
    /* Per-face materials: the quad's first triangle (lower right) red, its second green. */
    facet_scene* g = facet_scene_create();
    uint32_t gq = 0, red = 0, green = 0;
    CHECK(facet_scene_add_mesh(g, quad, 4, NULL, tris, 2, &gq) == FACET_OK);
    facet_material gm = facet_material_default();
    gm.ambient[0] = gm.ambient[1] = gm.ambient[2] = 0;
    gm.diffuse[0] = gm.diffuse[1] = gm.diffuse[2] = 0;
    gm.emissive[0] = 1;
    CHECK(facet_scene_add_material(g, &gm, &red) == FACET_OK);
    gm.emissive[0] = 0, gm.emissive[1] = 1;
    CHECK(facet_scene_add_material(g, &gm, &green) == FACET_OK);
    CHECK(facet_scene_add_object_with_mesh_materials(g, gq, NULL, NULL) == FACET_INVALID_ARGUMENT);
    const uint32_t counts[2] = {1, 1}, too_many[2] = {2, 1}, ids[2] = {red, green}, bad_ids[2] = {red, 7};
    CHECK(facet_scene_set_mesh_groups(g, gq, too_many, ids, 2) == FACET_INVALID_ARGUMENT);
    CHECK(facet_scene_set_mesh_groups(g, gq, counts, bad_ids, 2) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(g), "material_ids") != NULL);
    CHECK(facet_scene_set_mesh_groups(g, gq, counts, ids, 1) == FACET_INVALID_ARGUMENT); /* does not cover the mesh */
    CHECK(facet_scene_set_mesh_groups(g, gq, counts, ids, 2) == FACET_OK);
    CHECK(facet_scene_add_object_with_mesh_materials(g, gq, NULL, NULL) == FACET_OK);
    CHECK(facet_scene_set_camera(g, &cam) == FACET_OK);
    CHECK(facet_render(sr, g, img, 16, 16, 16 * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    const unsigned char* lower_right = img + 4 * (16 * 12 + 12);
    const unsigned char* upper_left = img + 4 * (16 * 3 + 3);
    CHECK(lower_right[0] == 255 && lower_right[1] == 0);
    CHECK(upper_left[0] == 0 && upper_left[1] == 255);
    facet_scene_destroy(g);

    facet_renderer_destroy(sr);
    facet_scene_destroy(s);
  }

  facet_renderer_destroy(renderer);
  facet_scene_destroy(scene);
  facet_renderer_destroy(NULL);
  facet_scene_destroy(NULL);
  if (failures == 0) printf("c_api_test: ok\n");
  /* Shadows, ray-cast, from a shadow map and from shadow volumes: a square over a floor under a
   * light from straight above (Phong). */
  for (int pass = 0; pass < 3; ++pass) {
    const facet_shadow_method method = pass == 0 ? FACET_SHADOW_RAYCAST : pass == 1 ? FACET_SHADOW_MAP : FACET_SHADOW_VOLUME;
    const float floor_and_square[] = {-2, 0, -2, 2, 0, -2, 2, 0, 2, -2, 0, 2,
                                      -0.5f, 1, -0.5f, 0.5f, 1, -0.5f, 0.5f, 1, 0.5f, -0.5f, 1, 0.5f};
    const uint32_t quad[] = {0, 2, 1, 0, 3, 2};
    const uint32_t square_quad[] = {4, 6, 5, 4, 7, 6};
    facet_scene* sh = facet_scene_create();
    uint32_t floor_mesh = 0, square_mesh = 0, mat = 0, floor_object = 0, square_object = 0;
    CHECK(facet_scene_add_mesh(sh, floor_and_square, 8, NULL, quad, 2, &floor_mesh) == FACET_OK);
    CHECK(facet_scene_add_mesh(sh, floor_and_square, 8, NULL, square_quad, 2, &square_mesh) == FACET_OK);
    facet_material grey = facet_material_default();
    CHECK(facet_scene_add_material(sh, &grey, &mat) == FACET_OK);
    CHECK(facet_scene_add_object(sh, floor_mesh, mat, NULL, &floor_object) == FACET_OK);
    CHECK(facet_scene_add_object(sh, square_mesh, mat, NULL, &square_object) == FACET_OK);
    facet_light down = facet_light_default();
    CHECK(down.shadow_method == FACET_SHADOW_NONE && down.shadow_resolution == 2048 &&
          down.shadow_filter == FACET_SHADOW_PCF3X3 && down.shadow_bias_normal > 0.0f);
    down.direction[0] = 0, down.direction[1] = -1, down.direction[2] = 0;
    facet_light bad_light = down;
    bad_light.shadow_method = (facet_shadow_method)9;
    CHECK(facet_scene_add_light(sh, &bad_light, NULL) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(sh), "shadow_method") != NULL);
    down.shadow_method = method;
    CHECK(facet_scene_add_light(sh, &down, NULL) == FACET_OK);
    CHECK(facet_scene_set_object_shadows(sh, 5, 1, 1) == FACET_INVALID_ARGUMENT);
    facet_camera above = facet_camera_default();
    above.eye[0] = 0, above.eye[1] = 6, above.eye[2] = 0.01f;
    above.target[0] = 0, above.target[1] = 0, above.target[2] = 0;
    CHECK(facet_scene_set_camera(sh, &above) == FACET_OK);
    facet_render_config phong = facet_render_config_default();
    phong.shading = FACET_PHONG;
    facet_renderer* r = facet_renderer_create(&phong, NULL);
    static unsigned char img[W * H * 4], unshadowed[W * H * 4];
    CHECK(facet_render(r, sh, img, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    CHECK(facet_scene_set_object_shadows(sh, square_object, 0, 1) == FACET_OK); /* casts nothing */
    CHECK(facet_render(r, sh, unshadowed, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    /* Straight above: the square's shadow is exactly under it and the camera sees the square,
     * not the shadow; so the two images agree on the square and on the lit floor, and the only
     * difference can be nowhere. With a second light from the side, the shadow shows. */
    CHECK(memcmp(img, unshadowed, sizeof img) == 0);
    facet_light side = facet_light_default();
    side.direction[0] = 0.8f, side.direction[1] = -0.6f, side.direction[2] = 0;
    side.shadow_method = method;
    CHECK(facet_scene_add_light(sh, &side, NULL) == FACET_OK);
    CHECK(facet_scene_set_object_shadows(sh, square_object, 1, 1) == FACET_OK);
    facet_frame_stats shadow_stats = {0};
    CHECK(facet_render(r, sh, img, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, &shadow_stats) == FACET_OK);
    CHECK(shadow_stats.shadow_casters == 4 && shadow_stats.seconds_shadows > 0.0);
    CHECK(method == FACET_SHADOW_MAP ? shadow_stats.shadow_map_texels == 2u * 2048u * 2048u &&
                                           shadow_stats.shadow_map_pixels > 0
                                     : shadow_stats.shadow_map_texels == 0);
    CHECK(facet_scene_set_object_shadows(sh, square_object, 0, 1) == FACET_OK);
    CHECK(facet_render(r, sh, unshadowed, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    int darker = 0, brighter = 0;
    for (int i = 0; i < W * H * 4; i += 4) {
      darker += img[i] < unshadowed[i];
      brighter += img[i] > unshadowed[i];
    }
    CHECK(darker > 20 && brighter == 0);
    /* Gouraud draws them too (per pixel): darker where the square shadows the floor. */
    facet_render_config gouraud = facet_render_config_default();
    facet_renderer* g = facet_renderer_create(&gouraud, NULL);
    CHECK(facet_scene_set_object_shadows(sh, square_object, 1, 1) == FACET_OK);
    CHECK(facet_render(g, sh, img, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    CHECK(facet_scene_set_object_shadows(sh, square_object, 0, 1) == FACET_OK);
    CHECK(facet_render(g, sh, unshadowed, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    darker = 0, brighter = 0;
    for (int i = 0; i < W * H * 4; i += 4) {
      darker += img[i] + 1 < unshadowed[i];
      brighter += img[i] > unshadowed[i] + 1;
    }
    CHECK(darker > 20 && brighter == 0);
    facet_renderer_destroy(g);
    facet_renderer_destroy(r);
    facet_scene_destroy(sh);
  }

  /* The scene model: version, stable ids, update and remove, switches, encoded textures, files. */
  {
    char version[32];
    snprintf(version, sizeof version, "%d.%d.%d", FACET_VERSION_MAJOR, FACET_VERSION_MINOR, FACET_VERSION_PATCH);
    CHECK(strcmp(facet_version(), version) == 0);
    CHECK(strcmp(facet_version(), FACET_VERSION_STRING) == 0);
    facet_scene* e = facet_scene_create();
    uint32_t mesh_e = 0, mat_a = 0, mat_b = 0, obj_a = 0, obj_b = 0, light_a = 0, light_b = 0;
    CHECK(facet_scene_add_mesh(e, positions, 6, NULL, indices, 8, &mesh_e) == FACET_OK);
    facet_material red = facet_material_default(), blue = facet_material_default();
    red.diffuse[0] = 1, red.diffuse[1] = 0, red.diffuse[2] = 0;
    blue.diffuse[0] = 0, blue.diffuse[1] = 0, blue.diffuse[2] = 1;
    CHECK(facet_scene_add_material(e, &red, &mat_a) == FACET_OK);
    CHECK(facet_scene_add_material(e, &blue, &mat_b) == FACET_OK);
    CHECK(facet_scene_add_object(e, mesh_e, mat_a, NULL, &obj_a) == FACET_OK);
    CHECK(facet_scene_add_object(e, mesh_e, mat_a, NULL, &obj_b) == FACET_OK);
    facet_light l1 = facet_light_default(), l2 = facet_light_default();
    CHECK(facet_scene_add_light(e, &l1, &light_a) == FACET_OK);
    CHECK(facet_scene_add_light(e, &l2, &light_b) == FACET_OK);
    CHECK(light_a == 0 && light_b == 1 && obj_a == 0 && obj_b == 1);
    facet_renderer* er = facet_renderer_create(NULL, NULL);
    static uint8_t before[W * H * 4], after[W * H * 4];
    facet_frame_stats st = {0};
    st.struct_size = sizeof st;
    CHECK(facet_render(er, e, before, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, &st) == FACET_OK);
    CHECK(st.struct_size == sizeof st && st.pixels_filled > 0);
    /* Removing object 0 keeps object 1's id; moving it away empties the frame, and says why. */
    CHECK(facet_scene_remove_object(e, obj_a) == FACET_OK);
    CHECK(facet_scene_remove_object(e, obj_a) == FACET_INVALID_ARGUMENT);
    const float far_away[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 100, 0, 0, 1};
    CHECK(facet_scene_set_object_transform(e, obj_b, far_away) == FACET_OK);
    CHECK(facet_render(er, e, after, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, &st) == FACET_OK);
    CHECK(st.pixels_filled == 0);
    char why[256];
    CHECK(facet_explain_empty_frame(&st, why, sizeof why) > 0 && strstr(why, "outside the view") != NULL);
    CHECK(facet_scene_set_object_transform(e, obj_b, NULL) == FACET_OK);
    /* The material changes the picture: red, then blue. */
    CHECK(facet_scene_set_object_material(e, obj_b, mat_b) == FACET_OK);
    CHECK(facet_render(er, e, after, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    int red_px = 0, blue_px = 0;
    for (int i = 0; i < W * H * 4; i += 4) red_px += before[i] > 100, blue_px += after[i + 2] > 100 && after[i] < 60;
    CHECK(red_px > 50 && blue_px > 50);
    CHECK(facet_scene_remove_material(e, mat_b) == FACET_INVALID_ARGUMENT); /* object 1 uses it */
    CHECK(facet_scene_remove_material(e, mat_a) == FACET_OK);
    CHECK(facet_scene_add_object(e, mesh_e, mat_a, NULL, NULL) == FACET_INVALID_ARGUMENT); /* removed */
    blue.diffuse[1] = 1;
    CHECK(facet_scene_set_material(e, mat_b, &blue) == FACET_OK);
    CHECK(blue.specular_model == FACET_SPECULAR_BLINN);
    blue.specular_model = FACET_SPECULAR_PHONG;
    CHECK(facet_scene_set_material(e, mat_b, &blue) == FACET_OK);
    blue.specular_model = (facet_specular_model)3;
    CHECK(facet_scene_set_material(e, mat_b, &blue) == FACET_INVALID_ARGUMENT);
    blue.specular_model = FACET_SPECULAR_PHONG;
    blue.shininess = -1;
    CHECK(facet_scene_set_material(e, mat_b, &blue) == FACET_INVALID_ARGUMENT);
    /* Lights: update (a smooth cone, a range, disabled) and remove by id. */
    facet_light spot = facet_light_default();
    spot.type = FACET_SPOT;
    spot.position[2] = 4;
    spot.spot_smooth = 1;
    spot.spot_inner_deg = 10, spot.spot_outer_deg = 20, spot.spot_falloff = 2;
    spot.range = 10;
    CHECK(facet_scene_set_light(e, light_b, &spot) == FACET_OK);
    spot.spot_inner_deg = 30; /* inner > outer */
    CHECK(facet_scene_set_light(e, light_b, &spot) == FACET_INVALID_ARGUMENT);
    spot.spot_inner_deg = 10;
    /* The linear min/max range: max must be > 0, min within [0, max]; an unknown model is refused. */
    CHECK(spot.attenuation_model == FACET_ATTENUATION_GL);
    spot.attenuation_model = FACET_ATTENUATION_LINEAR_RANGE;
    CHECK(facet_scene_set_light(e, light_b, &spot) == FACET_INVALID_ARGUMENT); /* max 0 */
    CHECK(strstr(facet_scene_last_error(e), "attenuation.max") != NULL);
    spot.range_min = 1, spot.range_max = 8;
    CHECK(facet_scene_set_light(e, light_b, &spot) == FACET_OK);
    spot.range_min = 9;
    CHECK(facet_scene_set_light(e, light_b, &spot) == FACET_INVALID_ARGUMENT);
    spot.range_min = 1;
    spot.attenuation_model = (facet_attenuation_model)5;
    CHECK(facet_scene_set_light(e, light_b, &spot) == FACET_INVALID_ARGUMENT);
    spot.attenuation_model = FACET_ATTENUATION_LINEAR_RANGE;
    /* A projector needs a texture that exists and a known mode. */
    CHECK(spot.projector_texture == -1 && spot.projector_mode == FACET_PROJECTOR_MODULATE);
    spot.projector_texture = 999;
    CHECK(facet_scene_set_light(e, light_b, &spot) == FACET_INVALID_ARGUMENT);
    spot.projector_texture = -1;
    spot.projector_mode = (facet_projector_mode)4;
    CHECK(facet_scene_set_light(e, light_b, &spot) == FACET_INVALID_ARGUMENT);
    spot.projector_mode = FACET_PROJECTOR_GOBO;
    CHECK(facet_scene_set_light(e, light_b, &spot) == FACET_OK);
    spot.enabled = 0;
    CHECK(facet_scene_set_light(e, light_b, &spot) == FACET_OK);
    CHECK(facet_scene_remove_light(e, light_a) == FACET_OK);
    CHECK(facet_scene_set_light(e, light_a, &spot) == FACET_INVALID_ARGUMENT);
    CHECK(facet_scene_set_two_sided(e, 1) == FACET_OK);
    CHECK(facet_scene_set_viewer(e, FACET_VIEWER_INFINITE) == FACET_OK);
    CHECK(facet_scene_set_viewer(e, (facet_viewer)7) == FACET_INVALID_ARGUMENT);
    CHECK(facet_scene_set_transparent_order(e, (facet_transparent_order)2) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(e), "order") != NULL);
    CHECK(facet_scene_set_transparent_order(e, FACET_TRANSPARENT_BACK_TO_FRONT) == FACET_OK);
    CHECK(facet_scene_set_object_double_sided(e, obj_b, 1) == FACET_OK);
    CHECK(facet_render(er, e, after, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
    /* A stats struct that is too small is refused before any pixel is written. */
    facet_frame_stats tiny = {0};
    tiny.struct_size = 8;
    memset(after, 0xAB, sizeof after);
    CHECK(facet_render(er, e, after, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, &tiny) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_renderer_last_error(er), "struct_size") != NULL);
    CHECK(after[0] == 0xAB && after[sizeof after - 1] == 0xAB);
    /* A texture from encoded bytes: not a PNG is refused with a message. */
    const uint8_t junk[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    CHECK(facet_scene_add_texture_encoded(e, junk, sizeof junk, FACET_TRILINEAR, FACET_WRAP_REPEAT, NULL) != FACET_OK);
    CHECK(strlen(facet_scene_last_error(e)) > 0);
    /* A model file: OBJ + MTL, framed and lit. */
    FILE* f = fopen("facet_c_api_test.mtl", "w");
    fputs("newmtl green\nKd 0 1 0\nmap_Ks specular.png\n", f);
    fclose(f);
    f = fopen("facet_c_api_test.obj", "w");
    fputs("mtllib facet_c_api_test.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl green\nf 1 2 3\n", f);
    fclose(f);
    CHECK(facet_scene_load_file(e, "facet_c_api_test.obj", FACET_LOAD_FRAME, (float)W / H, 0) == FACET_OK);
    CHECK(strstr(facet_scene_warnings(e), "map_Ks") != NULL);
    CHECK(facet_render(er, e, after, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, &st) == FACET_OK);
    CHECK(st.pixels_filled > 50);
    int green_px = 0;
    for (int i = 0; i < W * H * 4; i += 4) green_px += after[i + 1] > 100 && after[i] < 40;
    CHECK(green_px > 50);
    CHECK(facet_scene_load_file(e, "no_such_file.gltf", 0, 0, 0) == FACET_IO_ERROR);
    CHECK(strstr(facet_scene_last_error(e), "no_such_file.gltf") != NULL);
    CHECK(facet_render(er, e, after, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, &st) == FACET_OK); /* unchanged */
    CHECK(st.pixels_filled > 50);
    /* An mtllib that leads out of the model's folder is refused, and allowed once its folder is. */
    f = fopen("facet_c_api_test_out.obj", "w");
    fputs("mtllib ../facet_c_api_outside.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", f);
    fclose(f);
    CHECK(facet_scene_load_file(e, "facet_c_api_test_out.obj", FACET_LOAD_STRICT, 0, 0) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(e), "leads out") != NULL);
    /* By default a refused library is a warning: the model loads with facet's default material. */
    CHECK(facet_scene_load_file(e, "facet_c_api_test_out.obj", 0, 0, 0) == FACET_OK);
    CHECK(strstr(facet_scene_warnings(e), "leads out") != NULL);
    CHECK(facet_scene_load_file(e, "facet_c_api_test_out.obj", FACET_LOAD_STRICT | FACET_LOAD_ALLOW_MISSING, 0, 0) == FACET_INVALID_ARGUMENT);
    CHECK(facet_scene_allow_path(e, "..") == FACET_OK); /* allowed, and then merely missing: a warning */
    CHECK(facet_scene_load_file(e, "facet_c_api_test_out.obj", 0, 0, 0) == FACET_OK);
    CHECK(strstr(facet_scene_warnings(e), "leads out") == NULL);
    CHECK(facet_scene_allow_path(e, NULL) == FACET_OK);
    CHECK(facet_scene_load_file(e, "facet_c_api_test_out.obj", FACET_LOAD_STRICT, 0, 0) == FACET_INVALID_ARGUMENT);
    remove("facet_c_api_test_out.obj");
    /* A resolver: the model comes from memory, no file is opened. */
    CHECK(facet_scene_set_resolver(e, resolve_from_memory, NULL) == FACET_OK);
    CHECK(facet_scene_load_file(e, "mem/tri.obj", 0, 0, 0) == FACET_OK);
    CHECK(resolver_calls == 1);
    CHECK(facet_scene_load_file(e, "mem/other.obj", 0, 0, 0) == FACET_IO_ERROR);
    CHECK(facet_scene_set_resolver(e, NULL, NULL) == FACET_OK);
    remove("facet_c_api_test.obj");
    remove("facet_c_api_test.mtl");
    facet_renderer_destroy(er);
    facet_scene_destroy(e);
  }

  return failures == 0 ? 0 : 1;
}
