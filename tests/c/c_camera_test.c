/* Cameras from C: the orthographic projection (facet_scene_set_projection), framing with the
 * scene's projection and the six up axes, and a glTF file's camera picked by name
 * (facet_scene_set_load_camera, facet_scene_cameras). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "facet/facet.h"

#include "check.h"

enum { W = 32, H = 32 };

/* Covered pixels of a 2 x 2 emissive quad at depth z, seen by the scene's camera. */
static int covered(facet_scene* s, facet_renderer* r) {
  static unsigned char px[W * H * 4];
  CHECK(facet_render(r, s, px, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
  int n = 0;
  for (int i = 0; i < W * H; ++i) n += px[4 * i] != 0;
  return n;
}

/* A hash of the whole picture (FNV-1a over its bytes). */
static unsigned long long picture(facet_scene* s, facet_renderer* r) {
  static unsigned char px[W * H * 4];
  CHECK(facet_render(r, s, px, W, H, W * 4, FACET_RGBA8, 0, NULL, 0, NULL) == FACET_OK);
  unsigned long long h = 1469598103934665603ull;
  for (int i = 0; i < W * H * 4; ++i) h = (h ^ px[i]) * 1099511628211ull;
  return h;
}

static facet_scene* quad_at(float z) {
  facet_scene* s = facet_scene_create();
  const float quad[] = {-1, -1, z, 1, -1, z, 1, 1, z, -1, 1, z};
  const uint32_t tris[] = {0, 1, 2, 0, 2, 3};
  uint32_t mesh = 0, mat = 0;
  CHECK(facet_scene_add_mesh(s, quad, 4, NULL, tris, 2, &mesh) == FACET_OK);
  facet_material m = facet_material_default();
  m.emissive[0] = 1;
  CHECK(facet_scene_add_material(s, &m, &mat) == FACET_OK);
  CHECK(facet_scene_add_object(s, mesh, mat, NULL, NULL) == FACET_OK);
  facet_camera cam = facet_camera_default();
  cam.eye[0] = cam.eye[1] = cam.eye[2] = 0;
  cam.target[0] = 0, cam.target[1] = 0, cam.target[2] = -1;
  cam.near_plane = 0.5f;
  cam.far_plane = 50;
  CHECK(facet_scene_set_camera(s, &cam) == FACET_OK);
  return s;
}

int main(void) {
  facet_renderer* r = facet_renderer_create(NULL, NULL);
  /* Perspective by default; orthographic keeps a quad's size at every depth. */
  int sizes[2];
  for (int k = 0; k < 2; ++k) {
    facet_scene* s = quad_at(k == 0 ? -3.0f : -30.0f);
    facet_projection p = (facet_projection)9;
    float half = 0;
    CHECK(facet_scene_get_projection(s, &p, &half) == FACET_OK);
    CHECK(p == FACET_PROJECTION_PERSPECTIVE);
    CHECK(facet_scene_set_projection(s, FACET_PROJECTION_ORTHOGRAPHIC, 2.0f) == FACET_OK);
    CHECK(facet_scene_get_projection(s, &p, &half) == FACET_OK);
    CHECK(p == FACET_PROJECTION_ORTHOGRAPHIC && half == 2.0f);
    /* facet_scene_set_camera keeps the projection. */
    facet_camera cam;
    CHECK(facet_scene_get_camera(s, &cam) == FACET_OK);
    CHECK(facet_scene_set_camera(s, &cam) == FACET_OK);
    CHECK(facet_scene_get_projection(s, &p, &half) == FACET_OK && p == FACET_PROJECTION_ORTHOGRAPHIC);
    sizes[k] = covered(s, r);
    /* Refused, naming the field, and nothing changes. */
    CHECK(facet_scene_set_projection(s, FACET_PROJECTION_ORTHOGRAPHIC, 0.0f) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "camera.half_height") != NULL);
    CHECK(facet_scene_set_projection(s, (facet_projection)7, 1.0f) == FACET_INVALID_ARGUMENT);
    CHECK(facet_scene_get_projection(s, &p, &half) == FACET_OK && half == 2.0f);
    cam.far_plane = INFINITY;
    CHECK(facet_scene_set_camera(s, &cam) == FACET_INVALID_ARGUMENT);
    CHECK(strstr(facet_scene_last_error(s), "camera.far") != NULL);
    CHECK(facet_scene_get_projection(s, NULL, &half) == FACET_INVALID_ARGUMENT);
    facet_scene_destroy(s);
  }
  CHECK(sizes[0] == 16 * 16 && sizes[1] == sizes[0]);

  /* Framing keeps the scene's projection; every up axis is accepted, others refused. */
  facet_scene* s = quad_at(-3.0f);
  CHECK(facet_scene_set_projection(s, FACET_PROJECTION_ORTHOGRAPHIC, 1.0f) == FACET_OK);
  for (int up = FACET_UP_Y; up <= FACET_UP_NEG_Z; ++up) {
    CHECK(facet_scene_frame_view(s, 1.0f, 0, 0, (facet_up)up, 45, 0.85f) == FACET_OK);
  }
  facet_projection p = FACET_PROJECTION_PERSPECTIVE;
  float half = 0;
  CHECK(facet_scene_frame_view(s, 1.0f, 0, 0, FACET_UP_Y, 45, 0.5f) == FACET_OK);
  CHECK(facet_scene_get_projection(s, &p, &half) == FACET_OK);
  CHECK(p == FACET_PROJECTION_ORTHOGRAPHIC && fabsf(half - 2.0f) < 1e-4f); /* the quad's half height 1 over fill 0.5 */
  CHECK(facet_scene_frame_view(s, 1.0f, 0, 0, (facet_up)6, 45, 0.85f) == FACET_INVALID_ARGUMENT);
  CHECK(facet_scene_orbit(s, 30, FACET_UP_NEG_X, 0) == FACET_OK);
  facet_scene_destroy(s);

  /* A glTF file's second camera, by name; the file's cameras listed. */
  s = facet_scene_create();
  CHECK(facet_scene_set_load_camera(s, "Top") == FACET_OK);
  CHECK(facet_scene_load_file(s, FACET_TEST_DATA_DIR "/gltf/two_cameras.gltf", 0, 0, 0) == FACET_OK);
  CHECK(facet_scene_get_projection(s, &p, &half) == FACET_OK);
  CHECK(p == FACET_PROJECTION_ORTHOGRAPHIC && half == 1.5f);
  CHECK(strstr(facet_scene_cameras(s), "1 'Top' (node 'TopCam'), orthographic\n") != NULL);
  CHECK(facet_scene_set_load_camera(s, "Side") == FACET_OK);
  CHECK(facet_scene_load_file(s, FACET_TEST_DATA_DIR "/gltf/two_cameras.gltf", 0, 0, 0) == FACET_INVALID_ARGUMENT);
  CHECK(strstr(facet_scene_last_error(s), "no camera 'Side'") != NULL);
  CHECK(facet_scene_get_projection(s, &p, &half) == FACET_OK && p == FACET_PROJECTION_ORTHOGRAPHIC); /* unchanged */
  CHECK(facet_scene_set_load_camera(s, NULL) == FACET_OK);
  CHECK(facet_scene_load_file(s, FACET_TEST_DATA_DIR "/gltf/two_cameras.gltf", 0, 0, 0) == FACET_OK);
  CHECK(facet_scene_get_projection(s, &p, &half) == FACET_OK && p == FACET_PROJECTION_PERSPECTIVE);
  facet_scene_destroy(s);

  /* An animated glTF: its animations listed, posed at a time, back at rest with -1. */
  s = facet_scene_create();
  CHECK(facet_scene_load_file(s, FACET_TEST_DATA_DIR "/gltf/bending_strip.gltf", FACET_LOAD_FRAME, 1.0f, 0) == FACET_OK);
  CHECK(facet_scene_animation_count(s) == 2);
  const char* name = NULL;
  double start = -1, end = -1;
  CHECK(facet_scene_animation_info(s, 1, &name, &start, &end) == FACET_OK);
  CHECK(name && strcmp(name, "puff") == 0 && start == 0.0 && end == 2.0);
  CHECK(facet_scene_animation_info(s, 2, &name, &start, &end) == FACET_INVALID_ARGUMENT);
  const unsigned long long rest = picture(s, r);
  CHECK(facet_scene_pose(s, 0, 1.0) == FACET_OK);
  const unsigned long long bent = picture(s, r);
  CHECK(bent != rest);
  CHECK(facet_scene_pose(s, -1, 0.0) == FACET_OK);
  CHECK(picture(s, r) == rest);
  CHECK(facet_scene_pose(s, 2, 0.0) == FACET_INVALID_ARGUMENT);
  CHECK(strstr(facet_scene_last_error(s), "out of range") != NULL);
  CHECK(facet_scene_pose(s, 0, NAN) == FACET_INVALID_ARGUMENT);
  facet_scene_destroy(s);
  facet_renderer_destroy(r);
  if (failures) fprintf(stderr, "%d checks failed\n", failures);
  return failures ? 1 : 0;
}
