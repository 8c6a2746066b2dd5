/* Embedding facet from C: a triangle in the host's buffer. */
#include <stdio.h>

#include <facet/facet.h>

int main(void) {
  const float positions[] = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
  const uint32_t indices[] = {0, 1, 2};
  static unsigned char pixels[64 * 64 * 4];
  facet_scene* scene = facet_scene_create();
  uint32_t mesh = 0, material = 0;
  facet_material m = facet_material_default();
  facet_light light = facet_light_default();
  facet_camera camera = facet_camera_default();
  camera.eye[2] = 3.0f;
  if (facet_scene_add_mesh(scene, positions, 3, NULL, indices, 1, &mesh) != FACET_OK ||
      facet_scene_add_material(scene, &m, &material) != FACET_OK ||
      facet_scene_add_object(scene, mesh, material, NULL, NULL) != FACET_OK ||
      facet_scene_add_light(scene, &light, NULL) != FACET_OK || facet_scene_set_camera(scene, &camera) != FACET_OK) {
    fprintf(stderr, "scene: %s\n", facet_scene_last_error(scene));
    return 1;
  }
  facet_renderer* renderer = facet_renderer_create(NULL, NULL);
  facet_frame_stats stats = {0};
  if (facet_render(renderer, scene, pixels, 64, 64, 64 * 4, FACET_RGBA8, 0, NULL, 0, &stats) != FACET_OK) {
    fprintf(stderr, "render: %s\n", facet_renderer_last_error(renderer));
    return 1;
  }
  printf("%llu pixels filled\n", (unsigned long long)stats.pixels_filled);
  facet_renderer_destroy(renderer);
  facet_scene_destroy(scene);
  return stats.pixels_filled > 0 ? 0 : 1;
}
