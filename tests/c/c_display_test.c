/* Exposure and tone mapping from C (facet_display): defaults, validation with the field named,
 * exposure's doubling on float output, and the exposure a metered frame reports. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "facet/facet.h"

#include "check.h"

enum { S = 16 };

/* A quad facing the camera, lit head-on by a bright directional light. */
static facet_scene* lit_quad(void) {
  facet_scene* s = facet_scene_create();
  const float quad[] = {-2, -2, -3, 2, -2, -3, 2, 2, -3, -2, 2, -3};
  const uint32_t tris[] = {0, 1, 2, 0, 2, 3};
  uint32_t mesh = 0, mat = 0, light = 0;
  CHECK(facet_scene_add_mesh(s, quad, 4, NULL, tris, 2, &mesh) == FACET_OK);
  facet_material m = facet_material_default();
  CHECK(facet_scene_add_material(s, &m, &mat) == FACET_OK);
  CHECK(facet_scene_add_object(s, mesh, mat, NULL, NULL) == FACET_OK);
  facet_light l = facet_light_default();
  l.diffuse[0] = l.diffuse[1] = l.diffuse[2] = 40.0f;
  CHECK(facet_scene_add_light(s, &l, &light) == FACET_OK);
  facet_camera cam = facet_camera_default();
  cam.eye[0] = cam.eye[1] = cam.eye[2] = 0;
  cam.target[0] = 0, cam.target[1] = 0, cam.target[2] = -1;
  cam.vertical_fov_deg = 60;
  CHECK(facet_scene_set_camera(s, &cam) == FACET_OK);
  return s;
}

int main(void) {
  facet_scene* s = lit_quad();
  facet_display d;
  memset(&d, 0x5a, sizeof d);
  CHECK(facet_scene_get_display(s, &d) == FACET_OK);
  CHECK(d.exposure_ev == 0.0f && d.auto_exposure == 0 && d.tone_mapping == FACET_TONE_MAPPING_NONE);
  d.exposure_ev = 31.0f;
  CHECK(facet_scene_set_display(s, &d) == FACET_INVALID_ARGUMENT);
  CHECK(strstr(facet_scene_last_error(s), "display.ev") != NULL);
  d.exposure_ev = 0.0f;
  d.tone_mapping = (facet_tone_mapping)7;
  CHECK(facet_scene_set_display(s, &d) == FACET_INVALID_ARGUMENT);
  CHECK(strstr(facet_scene_last_error(s), "display.tone_mapping") != NULL);
  CHECK(facet_scene_set_display(s, NULL) == FACET_INVALID_ARGUMENT);

  facet_render_config rc = facet_render_config_default();
  rc.hdr = 1;
  facet_renderer* r = facet_renderer_create(&rc, NULL);
  static float base[S * S * 4], up[S * S * 4];
  d.tone_mapping = FACET_TONE_MAPPING_NEUTRAL;
  d.exposure_ev = -2.0f;
  CHECK(facet_scene_set_display(s, &d) == FACET_OK);
  facet_frame_stats st;
  memset(&st, 0, sizeof st);
  CHECK(facet_render(r, s, base, S, S, S * 16, FACET_RGBA32F, 0, NULL, 0, &st) == FACET_OK);
  CHECK(st.exposure_ev == -2.0f);
  d.exposure_ev = -1.0f;
  CHECK(facet_scene_set_display(s, &d) == FACET_OK);
  CHECK(facet_render(r, s, up, S, S, S * 16, FACET_RGBA32F, 0, NULL, 0, NULL) == FACET_OK);
  /* +1 stop doubles the light (HDR float output: the exposure alone). */
  CHECK(base[4 * (8 * S + 8)] > 1.0f);
  for (int i = 0; i < S * S * 4; ++i) {
    if (i % 4 != 3 && up[i] != 2.0f * base[i]) {
      CHECK(up[i] == 2.0f * base[i]);
      break;
    }
  }
  facet_renderer_destroy(r);

  /* Metered: the light of 40 on a white-ish quad needs about -8 stops to reach middle grey. */
  rc = facet_render_config_default();
  r = facet_renderer_create(&rc, NULL);
  d.auto_exposure = 1;
  CHECK(facet_scene_set_display(s, &d) == FACET_OK);
  static unsigned char px[S * S * 4];
  memset(&st, 0, sizeof st);
  CHECK(facet_render(r, s, px, S, S, S * 4, FACET_RGBA8, 0, NULL, 0, &st) == FACET_OK);
  CHECK(st.exposure_ev < -6.0f && st.exposure_ev > -10.0f);
  CHECK(px[4 * (8 * S + 8)] > 60 && px[4 * (8 * S + 8)] < 200);
  /* A struct from before exposure_ev existed (struct_size up to the field) is still accepted, and
   * the field is left alone. */
  memset(&st, 0, sizeof st);
  st.struct_size = offsetof(facet_frame_stats, exposure_ev);
  st.exposure_ev = 123.0f;
  CHECK(facet_render(r, s, px, S, S, S * 4, FACET_RGBA8, 0, NULL, 0, &st) == FACET_OK);
  CHECK(st.exposure_ev == 123.0f);
  facet_renderer_destroy(r);
  facet_scene_destroy(s);
  if (failures) fprintf(stderr, "%d checks failed\n", failures);
  return failures ? 1 : 0;
}
