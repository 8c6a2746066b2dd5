/* The C API's scene setters, from C: every setter changes the picture, and setting the old value
 * back restores it byte for byte. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "facet/facet.h"

#include "check.h"

enum { SW = 64, SH = 48 };

/* A progress callback that cancels. */
static int cancel_always(void* user, double done) {
  (void)user, (void)done;
  return 0;
}

/* Renders `scene` with `r`; the pixels filled. */
static uint64_t draw(facet_renderer* r, const facet_scene* scene, uint8_t* px) {
  facet_frame_stats st;
  memset(&st, 0, sizeof st);
  st.struct_size = sizeof st;
  if (facet_render(r, scene, px, SW, SH, SW * 4, FACET_RGBA8, 0, NULL, 0, &st) != FACET_OK) {
    fprintf(stderr, "render failed: %s\n", facet_renderer_last_error(r));
    ++failures;
  }
  return st.pixels_filled;
}

static int same(const uint8_t* a, const uint8_t* b) { return memcmp(a, b, SW * SH * 4) == 0; }

/* Every scene setter changes the picture (a setter that returns FACET_OK and changes nothing
 * fails here), and setting the old value back restores it byte for byte. The scene: an opaque
 * octahedron casting a ray-cast shadow on a floor, two blended quads overlapping in front of it
 * (submitted near one first, so that the order matters), a quad facing away beside it, a point
 * light with a specular highlight. */
static void setters_change_the_picture(void) {
  const float octa[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  const uint32_t octa_idx[] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  const float quad[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const uint32_t quad_idx[] = {0, 1, 2, 0, 2, 3};
  const uint32_t quad_back_idx[] = {0, 2, 1, 0, 3, 2};
  facet_scene* s = facet_scene_create();
  uint32_t m_octa, m_quad, m_back, red, blue, green, grey;
  CHECK(facet_scene_add_mesh(s, octa, 6, NULL, octa_idx, 8, &m_octa) == FACET_OK);
  CHECK(facet_scene_add_mesh(s, quad, 4, NULL, quad_idx, 2, &m_quad) == FACET_OK);
  CHECK(facet_scene_add_mesh(s, quad, 4, NULL, quad_back_idx, 2, &m_back) == FACET_OK);
  facet_material m = facet_material_default();
  m.diffuse[0] = 0.9f, m.diffuse[1] = 0.2f, m.diffuse[2] = 0.1f;
  m.specular[0] = m.specular[1] = m.specular[2] = 1.0f;
  m.shininess = 12.0f;
  CHECK(facet_scene_add_material(s, &m, &red) == FACET_OK);
  facet_material b = facet_material_default();
  b.diffuse[0] = 0.1f, b.diffuse[1] = 0.2f, b.diffuse[2] = 0.9f, b.alpha = 0.5f, b.blend = FACET_BLEND_ALPHA;
  CHECK(facet_scene_add_material(s, &b, &blue) == FACET_OK);
  b.diffuse[0] = 0.1f, b.diffuse[1] = 0.9f, b.diffuse[2] = 0.2f;
  CHECK(facet_scene_add_material(s, &b, &green) == FACET_OK);
  facet_material g = facet_material_default();
  CHECK(facet_scene_add_material(s, &g, &grey) == FACET_OK);
  const float at_origin[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  float floor_m[16] = {3, 0, 0, 0, 0, 3, 0, 0, 0, 0, 1, 0, 0, 0, -1.5f, 1};
  float near_q[16] = {0.6f, 0, 0, 0, 0, 0.6f, 0, 0, 0, 0, 1, 0, 0.4f, 0, 1.6f, 1};
  float far_q[16] = {0.6f, 0, 0, 0, 0, 0.6f, 0, 0, 0, 0, 1, 0, -0.4f, 0, 1.3f, 1};
  float side_q[16] = {0.5f, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0, 1, 0, 2.2f, 0.5f, 0, 1};
  uint32_t o_octa, o_floor, o_near, o_far, o_side;
  CHECK(facet_scene_add_object(s, m_octa, red, at_origin, &o_octa) == FACET_OK);
  CHECK(facet_scene_add_object(s, m_quad, grey, floor_m, &o_floor) == FACET_OK);
  CHECK(facet_scene_add_object(s, m_quad, green, near_q, &o_near) == FACET_OK);
  CHECK(facet_scene_add_object(s, m_quad, blue, far_q, &o_far) == FACET_OK);
  CHECK(facet_scene_add_object(s, m_back, grey, side_q, &o_side) == FACET_OK);
  facet_light l = facet_light_default();
  l.type = FACET_POINT;
  l.position[0] = 2.0f, l.position[1] = 2.5f, l.position[2] = 5.0f;
  l.specular[0] = l.specular[1] = l.specular[2] = 1.0f;
  l.shadow_method = FACET_SHADOW_RAYCAST;
  uint32_t light;
  CHECK(facet_scene_add_light(s, &l, &light) == FACET_OK);
  facet_camera cam = facet_camera_default();
  cam.eye[0] = 0.5f, cam.eye[1] = 0.5f, cam.eye[2] = 6.0f;
  CHECK(facet_scene_set_camera(s, &cam) == FACET_OK);
  facet_render_config config = facet_render_config_default();
  config.threads = 1;
  facet_renderer* r = facet_renderer_create(&config, NULL);
  config.cull = FACET_CULL_NONE;
  facet_renderer* r_all = facet_renderer_create(&config, NULL);
  static uint8_t base[SW * SH * 4], base_all[SW * SH * 4], px[SW * SH * 4];
  CHECK(draw(r, s, base) > SW * SH / 4);
  draw(r_all, s, base_all);
#define CHANGES(what, set_new, set_old)                                                        \
  do {                                                                                         \
    CHECK((set_new) == FACET_OK);                                                              \
    draw(r, s, px);                                                                            \
    if (same(px, base)) fprintf(stderr, "%s: the picture did not change\n", what), ++failures; \
    CHECK((set_old) == FACET_OK);                                                              \
    draw(r, s, px);                                                                            \
    if (!same(px, base)) fprintf(stderr, "%s: the picture did not come back\n", what), ++failures; \
  } while (0)
  const float moved[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -0.7f, 0, 0, 1};
  CHANGES("set_object_transform", facet_scene_set_object_transform(s, o_octa, moved),
          facet_scene_set_object_transform(s, o_octa, at_origin));
  CHANGES("set_object_material", facet_scene_set_object_material(s, o_octa, grey), facet_scene_set_object_material(s, o_octa, red));
  CHANGES("set_object_double_sided", facet_scene_set_object_double_sided(s, o_side, 1),
          facet_scene_set_object_double_sided(s, o_side, 0));
  facet_material m2 = m;
  m2.shininess = 80.0f;
  CHANGES("set_material", facet_scene_set_material(s, red, &m2), facet_scene_set_material(s, red, &m));
  CHANGES("set_viewer", facet_scene_set_viewer(s, FACET_VIEWER_INFINITE), facet_scene_set_viewer(s, FACET_VIEWER_LOCAL));
  CHANGES("set_transparent_order", facet_scene_set_transparent_order(s, FACET_TRANSPARENT_BACK_TO_FRONT),
          facet_scene_set_transparent_order(s, FACET_TRANSPARENT_SUBMISSION));
  CHANGES("set_object_shadows cast", facet_scene_set_object_shadows(s, o_octa, 0, 1), facet_scene_set_object_shadows(s, o_octa, 1, 1));
  CHANGES("set_object_shadows receive", facet_scene_set_object_shadows(s, o_floor, 1, 0),
          facet_scene_set_object_shadows(s, o_floor, 1, 1));
  facet_camera cam2 = cam;
  cam2.vertical_fov_deg = 30.0f;
  CHANGES("set_camera", facet_scene_set_camera(s, &cam2), facet_scene_set_camera(s, &cam));
  const float ambient2[3] = {0.5f, 0.5f, 0.5f}, ambient[3] = {0.2f, 0.2f, 0.2f};
  CHANGES("set_global_ambient", facet_scene_set_global_ambient(s, ambient2), facet_scene_set_global_ambient(s, ambient));
  facet_fog fog = facet_fog_default(), no_fog = facet_fog_default();
  fog.mode = FACET_FOG_LINEAR, fog.start = 4.0f, fog.end = 9.0f, fog.color[0] = 1.0f;
  CHANGES("set_fog", facet_scene_set_fog(s, &fog), facet_scene_set_fog(s, &no_fog));
  facet_light l2 = l;
  l2.position[0] = -3.0f;
  CHANGES("set_light", facet_scene_set_light(s, light, &l2), facet_scene_set_light(s, light, &l));
  const float colors[12] = {1, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1, 1};
  CHANGES("set_mesh_colors", facet_scene_set_mesh_colors(s, m_quad, colors), facet_scene_set_mesh_colors(s, m_quad, NULL));
  /* Baked light on the floor: lightmap coordinates for its mesh, a one-texel lightmap. */
  {
    const float lightmap_uvs[8] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
    const uint8_t orange[4] = {255, 96, 0, 255};
    uint32_t lightmap;
    CHECK(facet_scene_add_texture_rgba8(s, orange, 1, 1, FACET_BILINEAR, FACET_WRAP_CLAMP, &lightmap) == FACET_OK);
    CHECK(facet_scene_set_object_lightmap(s, o_floor, (int32_t)lightmap, 1.0f, FACET_LIGHTMAP_DIFFUSE) != FACET_OK);
    CHECK(strstr(facet_scene_last_error(s), "lightmap coordinates") != NULL);
    CHECK(facet_scene_set_mesh_lightmap_uvs(s, m_quad, lightmap_uvs) == FACET_OK);
    CHECK(facet_scene_set_object_lightmap(s, o_floor, (int32_t)lightmap, 0.0f, FACET_LIGHTMAP_DIFFUSE) != FACET_OK);
    CHECK(strstr(facet_scene_last_error(s), "scale") != NULL);
    CHECK(facet_scene_set_object_lightmap(s, o_floor, 99, 1.0f, FACET_LIGHTMAP_DIFFUSE) != FACET_OK);
    CHANGES("set_object_lightmap", facet_scene_set_object_lightmap(s, o_floor, (int32_t)lightmap, 1.5f, FACET_LIGHTMAP_REPLACE),
            facet_scene_set_object_lightmap(s, o_floor, -1, 1.0f, FACET_LIGHTMAP_DIFFUSE));
    CHECK(facet_scene_set_mesh_lightmap_uvs(s, m_quad, NULL) == FACET_OK);
  }
  /* An environment map: a cube of six one-texel faces, mixed in at full strength. */
  {
    uint32_t faces[6];
    const uint8_t face_rgba[6][4] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255},
                                     {255, 255, 0, 255}, {0, 255, 255, 255}, {255, 0, 255, 255}};
    for (int k = 0; k < 6; ++k) {
      CHECK(facet_scene_add_texture_rgba8(s, face_rgba[k], 1, 1, FACET_BILINEAR, FACET_WRAP_CLAMP, &faces[k]) == FACET_OK);
    }
    facet_material chrome = m;
    CHECK(chrome.environment_mode == FACET_ENVIRONMENT_NONE && chrome.environment_maps[0] == -1 &&
          chrome.environment_strength == 1.0f && chrome.environment_blend == FACET_ENVIRONMENT_ADD);
    chrome.environment_mode = FACET_ENVIRONMENT_CUBE;
    chrome.environment_blend = FACET_ENVIRONMENT_MIX;
    for (int k = 0; k < 6; ++k) chrome.environment_maps[k] = (int32_t)faces[k];
    CHANGES("environment", facet_scene_set_material(s, red, &chrome), facet_scene_set_material(s, red, &m));
    CHECK(chrome.environment_dynamic == 0 && chrome.environment_resolution == 128);
    facet_material dynamic = chrome;
    for (int k = 0; k < 6; ++k) dynamic.environment_maps[k] = -1;
    dynamic.environment_dynamic = 1;
    dynamic.environment_resolution = 16;
    CHANGES("dynamic environment", facet_scene_set_material(s, red, &dynamic), facet_scene_set_material(s, red, &m));
    dynamic.environment_resolution = 0;
    CHECK(facet_scene_set_material(s, red, &dynamic) == FACET_INVALID_ARGUMENT);
    facet_material bad = chrome;
    bad.environment_maps[5] = -1;
    CHECK(facet_scene_set_material(s, red, &bad) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "environment.maps[5]") != NULL);
    bad = chrome;
    bad.environment_mode = (facet_environment_mode)9;
    CHECK(facet_scene_set_material(s, red, &bad) == FACET_INVALID_ARGUMENT);
    bad = chrome;
    bad.environment_maps[2] = 9999;
    CHECK(facet_scene_set_material(s, red, &bad) == FACET_INVALID_ARGUMENT);
    /* The same from an equirectangular picture: its top half white (the sky, +Y), bottom black. */
    uint8_t pano[8 * 4 * 4];
    for (int k = 0; k < 8 * 4; ++k) {
      const uint8_t v = k < 16 ? 255 : 0; /* rows bottom first: the last two rows are the top */
      pano[4 * k] = pano[4 * k + 1] = pano[4 * k + 2] = (uint8_t)(255 - v), pano[4 * k + 3] = 255;
    }
    uint32_t picture = 0, first = 0;
    CHECK(facet_scene_add_texture_rgba8(s, pano, 8, 4, FACET_BILINEAR, FACET_WRAP_REPEAT, &picture) == FACET_OK);
    CHECK(facet_scene_add_cube_from_equirect(s, picture, 4, &first) == FACET_OK && first == picture + 1);
    facet_material pano_chrome = chrome;
    for (int k = 0; k < 6; ++k) pano_chrome.environment_maps[k] = (int32_t)(first + (uint32_t)k);
    CHANGES("environment from a picture", facet_scene_set_material(s, red, &pano_chrome), facet_scene_set_material(s, red, &m));
    CHECK(facet_scene_add_cube_from_equirect(s, 9999, 4, &first) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "texture_id") != NULL);
    CHECK(facet_scene_add_cube_from_equirect(s, picture, 0, &first) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "face_size") != NULL);
  }
  /* Two-sided lighting shows on back faces that are drawn: with culling off. */
  CHECK(facet_scene_set_two_sided(s, 1) == FACET_OK);
  draw(r_all, s, px);
  if (same(px, base_all)) fprintf(stderr, "set_two_sided: the picture did not change\n"), ++failures;
  CHECK(facet_scene_set_two_sided(s, 0) == FACET_OK);
  draw(r_all, s, px);
  CHECK(same(px, base_all));
#undef CHANGES

  /* An infinite far plane, reversed depth: the depth output is near / w (1 at the near plane, 0
   * where nothing was drawn). */
  {
    facet_camera inf = cam;
    inf.far_plane = INFINITY;
    CHECK(facet_scene_set_camera(s, &inf) == FACET_OK);
    facet_render_config rc = facet_render_config_default();
    CHECK(rc.depth_mode == FACET_DEPTH_AUTO);
    rc.depth_mode = FACET_DEPTH_REVERSED;
    facet_renderer* rr = facet_renderer_create(&rc, NULL);
    static float depth[SW * SH];
    facet_frame_stats st;
    memset(&st, 0, sizeof st);
    CHECK(facet_render(rr, s, px, SW, SH, SW * 4, FACET_RGBA8, 0, depth, SW * sizeof(float), &st) == FACET_OK);
    int near_over_w = 0, nothing = 0;
    for (int i = 0; i < SW * SH; ++i) near_over_w += depth[i] > 0.0f && depth[i] < 0.1f, nothing += depth[i] == 0.0f;
    CHECK(near_over_w > SW * SH / 4 && nothing > 0 && near_over_w + nothing == SW * SH);
    facet_renderer_destroy(rr);
    rc.depth_mode = (facet_depth_mode)7;
    facet_status why = FACET_OK;
    CHECK(facet_renderer_create(&rc, &why) == NULL && why == FACET_INVALID_ARGUMENT);
    CHECK(facet_scene_set_camera(s, &cam) == FACET_OK);
  }

  /* A ninth enabled shadowed light is refused when it is added or set, not only at render. */
  {
    facet_scene* lit = facet_scene_create();
    facet_light shadowed = facet_light_default();
    shadowed.shadow_method = FACET_SHADOW_RAYCAST;
    uint32_t ids[9];
    for (int i = 0; i < 8; ++i) CHECK(facet_scene_add_light(lit, &shadowed, &ids[i]) == FACET_OK);
    CHECK(facet_scene_add_light(lit, &shadowed, &ids[8]) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(lit), "at most 8") != NULL);
    facet_light plain = facet_light_default();
    CHECK(facet_scene_add_light(lit, &plain, &ids[8]) == FACET_OK);
    CHECK(facet_scene_set_light(lit, ids[8], &shadowed) == FACET_INVALID_ARGUMENT);
    CHECK(facet_scene_set_light(lit, ids[0], &shadowed) == FACET_OK); /* replacing one of the eight */
    shadowed.enabled = 0;
    CHECK(facet_scene_set_light(lit, ids[8], &shadowed) == FACET_OK); /* disabled: casts nothing */
    facet_scene_destroy(lit);
  }

  /* Framing from a view, and a turntable's step. */
  facet_camera got;
  CHECK(facet_scene_frame_view(s, (float)SW / SH, 90.0f, 0.0f, FACET_UP_Y, 45.0f, 0.85f) == FACET_OK);
  CHECK(facet_scene_get_camera(s, &got) == FACET_OK);
  CHECK(got.eye[0] - got.target[0] > 1.0f && fabsf(got.eye[2] - got.target[2]) < 1e-3f); /* from +X */
  CHECK(draw(r, s, px) > 60); /* the floor, seen edge-on, is the tallest: the octahedron is small */
  CHECK(facet_scene_orbit(s, 90.0f, FACET_UP_Y, 1) == FACET_OK); /* +X turns to -Z, about the box's centre */
  CHECK(facet_scene_get_camera(s, &got) == FACET_OK);
  CHECK(got.target[2] - got.eye[2] > 5.0f && fabsf(got.eye[0] - got.target[0]) < 0.5f);
  CHECK(draw(r, s, px) > 60);
  CHECK(facet_scene_frame_view(s, 1.0f, 0.0f, 0.0f, FACET_UP_Z, 45.0f, 0.85f) == FACET_OK);
  CHECK(facet_scene_get_camera(s, &got) == FACET_OK);
  CHECK(got.eye[1] < got.target[1] && got.up[2] == 1.0f); /* Z up: the front faces -Y */
  CHECK(facet_scene_frame_view(s, 1.0f, 0.0f, 90.0f, FACET_UP_Y, 45.0f, 0.85f) == FACET_INVALID_ARGUMENT);
  CHECK(strstr(facet_scene_last_error(s), "elevation_deg") != NULL);
  CHECK(facet_scene_frame_view(s, 1.0f, 0.0f, 0.0f, (facet_up)6, 45.0f, 0.85f) == FACET_INVALID_ARGUMENT);
  CHECK(facet_scene_frame_view(s, 1.0f, 0.0f, 0.0f, FACET_UP_Y, 45.0f, 0.0f) == FACET_INVALID_ARGUMENT);
  CHECK(strstr(facet_scene_last_error(s), "fill") != NULL);
  CHECK(facet_scene_orbit(s, NAN, FACET_UP_Y, 0) == FACET_INVALID_ARGUMENT);
  CHECK(facet_scene_get_camera(s, NULL) == FACET_INVALID_ARGUMENT);
  /* Baking: a cancelled bake and a refused one leave the scene as it was; a bake changes the
   * picture (bounced light, baked shadows) and reports what it did. */
  {
    static uint8_t before[SW * SH * 4], after[SW * SH * 4];
    draw(r, s, before);
    facet_bake_config bc = facet_bake_config_default();
    CHECK(bc.texels_per_unit == 16.0 && bc.padding == 2 && bc.lights == 1 && bc.radiosity == 1 && bc.scale == 0.0 &&
          bc.burial_rays == 16 && bc.use_mesh_uvs == 1 && bc.small_texel == 0.25);
    bc.texels_per_unit = 4.0;
    bc.max_shots = 200;
    bc.rays_per_shot = 32;
    bc.progress = cancel_always;
    CHECK(facet_scene_bake(s, &bc, NULL) == FACET_CANCELLED);
    draw(r, s, after);
    CHECK(same(before, after));
    bc.progress = NULL;
    bc.texels_per_unit = 1e7;
    CHECK(facet_scene_bake(s, &bc, NULL) == FACET_OUT_OF_MEMORY);
    CHECK(strstr(facet_scene_last_error(s), "would fit") != NULL);
    draw(r, s, after);
    CHECK(same(before, after));
    bc.texels_per_unit = 4.0;
    bc.mode = (facet_lightmap_mode)9;
    CHECK(facet_scene_bake(s, &bc, NULL) == FACET_INVALID_ARGUMENT);
    bc.mode = FACET_LIGHTMAP_DIFFUSE;
    bc.burial_rays = 2000;
    CHECK(facet_scene_bake(s, &bc, NULL) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "burial_rays") != NULL);
    bc.burial_rays = 16;
    facet_bake_stats bs;
    memset(&bs, 0, sizeof bs);
    CHECK(facet_scene_bake(s, &bc, &bs) == FACET_OK);
    CHECK(bs.patches > 0 && bs.rays > 0 && bs.shots > 0 && bs.scale > 0.0 && bs.entered > 0.0);
    draw(r, s, after);
    CHECK(!same(before, after));
  }
  facet_scene* empty = facet_scene_create();
  CHECK(facet_scene_frame(empty, 1.0f) == FACET_INVALID_ARGUMENT); /* nothing to frame */
  CHECK(facet_scene_orbit(empty, 10.0f, FACET_UP_Y, 0) == FACET_INVALID_ARGUMENT);
  facet_scene_destroy(empty);
  facet_renderer_destroy(r);
  facet_renderer_destroy(r_all);
  facet_scene_destroy(s);
}

int main(void) {
  setters_change_the_picture();
  return failures == 0 ? 0 : 1;
}
