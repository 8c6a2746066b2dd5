/* facet's C API: opaque handles over the C++ library, for hosts written in C or any language with
 * a C FFI. Link with -lfacet (see facet.pc) or CMake's facet::engine.
 *
 * Errors: every fallible call returns a facet_status; FACET_OK (0) is success. The complete
 * message of the last failure (naming the argument or field) is kept per handle:
 * facet_renderer_last_error / facet_scene_last_error. Nothing aborts and nothing is printed.
 * A failed call changes nothing: a failed render writes no pixel.
 *
 * Threads: a handle is used by one thread at a time. Different renderers may render at the same
 * time from different threads, also the same scene (rendering only reads it).
 *
 * Conventions (as the C++ API): right-handed world, the camera looks down -z in eye space;
 * window depth 0 = near plane, 1 = far plane; counter-clockwise triangles face the viewer;
 * matrices are 4x4 column-major (OpenGL order); colours are linear RGB in [0, 1]. */
#ifndef FACET_FACET_H
#define FACET_FACET_H

#include <stddef.h>
#include <stdint.h>

#include "facet/version.h" /* FACET_VERSION_MAJOR, _MINOR, _PATCH and FACET_VERSION_STRING */

#ifdef __cplusplus
extern "C" {
#endif

typedef enum facet_status {
  FACET_OK = 0,
  FACET_INVALID_ARGUMENT = 1, /* a value outside its documented domain (NaN, bad index, size...) */
  FACET_PARSE_ERROR = 2,      /* a file is not well-formed */
  FACET_IO_ERROR = 3,         /* a file cannot be read or written */
  FACET_UNSUPPORTED = 4,      /* e.g. an instruction set this CPU does not have */
  FACET_OUT_OF_MEMORY = 5,    /* an allocation failed, or the frame would exceed its memory budget */
  FACET_CANCELLED = 6         /* the progress callback returned 0 */
} facet_status;

typedef enum facet_pixel_format { FACET_RGBA8 = 0, FACET_BGRA8 = 1, FACET_RGBA32F = 2 } facet_pixel_format;
typedef enum facet_shading { FACET_FLAT = 0, FACET_GOURAUD = 1, FACET_PHONG = 2 } facet_shading;
typedef enum facet_path { FACET_PATH_REFERENCE = 0, FACET_PATH_SCALAR = 1, FACET_PATH_SIMD = 2 } facet_path;
typedef enum facet_isa { FACET_ISA_BEST = 0, FACET_ISA_SSE2 = 1, FACET_ISA_AVX2 = 2, FACET_ISA_AVX512 = 3 } facet_isa;
typedef enum facet_cull { FACET_CULL_NONE = 0, FACET_CULL_BACK = 1, FACET_CULL_FRONT = 2 } facet_cull;
typedef enum facet_light_type { FACET_DIRECTIONAL = 0, FACET_POINT = 1, FACET_SPOT = 2 } facet_light_type;
/* Surfaces: see docs/surfaces.md (the C++ enums TextureFilter, TextureWrap, TextureMode, BlendMode,
 * DepthWrite and FogMode, in the same order). */
typedef enum facet_texture_filter { FACET_NEAREST = 0, FACET_BILINEAR = 1, FACET_TRILINEAR = 2 } facet_texture_filter;
typedef enum facet_texture_wrap { FACET_WRAP_REPEAT = 0, FACET_WRAP_CLAMP = 1, FACET_WRAP_MIRROR = 2 } facet_texture_wrap;
typedef enum facet_texture_mode {
  FACET_MODULATE = 0, FACET_REPLACE = 1, FACET_DECAL = 2, FACET_ADD = 3
} facet_texture_mode;
typedef enum facet_lightmap_mode { FACET_LIGHTMAP_DIFFUSE = 0, FACET_LIGHTMAP_REPLACE = 1 } facet_lightmap_mode;
typedef enum facet_blend {
  FACET_BLEND_OPAQUE = 0, FACET_BLEND_ALPHA = 1, FACET_BLEND_PREMULTIPLIED = 2,
  FACET_BLEND_ADD = 3, FACET_BLEND_MULTIPLY = 4, FACET_BLEND_SUBTRACT = 5
} facet_blend;
typedef enum facet_depth_write { FACET_DEPTH_WRITE_AUTO = 0, FACET_DEPTH_WRITE_ON = 1, FACET_DEPTH_WRITE_OFF = 2 } facet_depth_write;
typedef enum facet_fog_mode { FACET_FOG_NONE = 0, FACET_FOG_LINEAR = 1, FACET_FOG_EXP = 2, FACET_FOG_EXP2 = 3 } facet_fog_mode;
/* Environment mapping (facet::Environment): the lookup, and how the map's colour combines. */
typedef enum facet_environment_mode {
  FACET_ENVIRONMENT_NONE = 0, FACET_ENVIRONMENT_SPHERE = 1, FACET_ENVIRONMENT_CUBE = 2, FACET_ENVIRONMENT_NORMAL = 3
} facet_environment_mode;
typedef enum facet_environment_blend {
  FACET_ENVIRONMENT_ADD = 0, FACET_ENVIRONMENT_MODULATE = 1, FACET_ENVIRONMENT_MIX = 2
} facet_environment_blend;

/* How the simd path evaluates x^s (specular shininess, spot exponent); see docs. */
typedef enum facet_pixel_precision {
  FACET_PIXELS_AUTO = 0,
  FACET_PIXELS_EXACT = 1,
  FACET_PIXELS_FAST = 2
} facet_pixel_precision;

typedef enum facet_pow_tier {
  FACET_POW_AUTO = 0,    /* per exponent, the cheapest tier within 1 step of 8-bit output */
  FACET_POW_EXACT = 1,   /* full-precision exp2(s log2 x) */
  FACET_POW_FAST = 2,    /* polynomial log2/exp2: 8-bit output within 1 step */
  FACET_POW_INTEGER = 3, /* repeated squaring; whole exponents <= 256 only (others use exact) */
  FACET_POW_SCHLICK = 4  /* Schlick's rational lobe: a different specular model */
} facet_pow_tier;

typedef enum facet_depth_mode { FACET_DEPTH_AUTO = 0, FACET_DEPTH_GL = 1, FACET_DEPTH_REVERSED = 2 } facet_depth_mode;

/* How a renderer renders. Start from facet_render_config_default(). */
typedef struct facet_render_config {
  facet_shading shading;
  facet_path path;
  facet_isa isa;       /* simd path: the instruction set (FACET_ISA_BEST: the widest available) */
  facet_cull cull;
  int tile_size;       /* 8..256, a multiple of 8 */
  int threads;         /* 0 = all cores, else 1..256; the image is the same for any value */
  float clear_color[4];
  int srgb; /* non-zero (default): 8-bit output is sRGB-encoded (exactly rounded); alpha and float
             * output stay linear. 0: the lit values as they are (GL 2.1's framebuffer). */
  /* The most scratch memory one frame may take (estimated before allocating; a frame over it
   * fails with FACET_OUT_OF_MEMORY before any pixel is written); 0 = no limit. Default 4 GiB. */
  uint64_t memory_budget_bytes;
  /* Optional (NULL: none): called from the renderer's threads, one call at a time, with the share
   * of the frame done in [0, 1]; return 0 to cancel (facet_render then returns FACET_CANCELLED;
   * pixels may be partly written if the tiles had started). */
  int (*progress)(void* user, double done);
  void* progress_user;
  facet_pow_tier pow_tier; /* simd path only; default FACET_POW_AUTO */
  int hdr;                 /* non-zero: RGBA32F output keeps unclamped (>= 0) lighting */
  int cull_lights;         /* non-zero (default): skip lights that cannot reach an object */
  /* non-zero: light every vertex (flat: every triangle), not only those of triangles that can be
   * drawn; the image is the same bytes either way (facet_frame_stats.vertices_skipped counts the
   * difference). Default 0; for measurements. */
  int light_every_vertex;
  /* How the camera pass stores depth (facet::DepthMode): FACET_DEPTH_AUTO (default: reversed when
   * the camera's far plane is infinite or more than 1e5 times its near plane), FACET_DEPTH_GL
   * (GL's window depth; the depth output is 0 near, 1 far), FACET_DEPTH_REVERSED (reversed-Z in a
   * float: no z-fighting at near / far ratios like 0.05 / 1e6; the depth output is near / w, 1 at
   * the near plane, 0 at infinity). A camera's far_plane may be INFINITY: an infinite projection. */
  facet_depth_mode depth_mode;
  /* non-zero: Gouraud lights each vertex of a normal- or bump-mapped object with its normal
   * perturbed by the maps (read at the vertex, prefiltered to the mesh's triangle size); 0
   * (default, GL's fixed function): the maps are read per pixel in Phong only. */
  int vertex_relief;
  /* Textured pixels (facet::PixelPrecision): FACET_PIXELS_AUTO (default: the fast tier where it
   * is within its contract and faster; today the exact tier), FACET_PIXELS_EXACT (float),
   * FACET_PIXELS_FAST (the 16-bit tier: linear diffuse textures filtered in fixed point). */
  facet_pixel_precision pixel_precision;
  /* Samples per pixel (facet::RenderOptions::samples): 1 (default), 4, 8 or 16. GL's
   * multisampling: coverage and depth per sample, each pixel shaded once, the samples averaged in
   * linear colour. Any other count fails with FACET_INVALID_ARGUMENT naming config.samples. */
  int samples;
} facet_render_config;

/* The specular lobe (facet::SpecularModel): Blinn's n.h (GL's) or Phong's R.V. */
typedef enum facet_specular_model { FACET_SPECULAR_BLINN = 0, FACET_SPECULAR_PHONG = 1 } facet_specular_model;

typedef struct facet_material {
  float emissive[3], ambient[3], diffuse[3], specular[3];
  float shininess; /* [0, 4096] */
  float alpha;     /* [0, 1] */
  int32_t diffuse_texture;         /* a facet_scene_add_texture* id, or -1 for none */
  facet_texture_mode texture_mode; /* default FACET_MODULATE */
  float uv_scale[2];               /* finite, non-zero; default 1, 1 */
  float alpha_cutoff;              /* [0, 1]; alpha test, 0 = off */
  facet_blend blend;               /* default FACET_BLEND_OPAQUE */
  facet_depth_write depth_write;   /* default FACET_DEPTH_WRITE_AUTO: opaque writes, blended does not */
  /* Emission after texturing (glTF's rule; facet::Material): emissive times this texture's RGB,
   * added after the texture environment. -1: none (default). */
  int32_t emissive_texture;
  int emission_after_texture; /* non-zero: the emission is added after the texture environment even
                                 without emissive_texture (GL, default 0: the diffuse texture modulates it) */
  /* Environment mapping after the texture environment (docs/environment.md). Sphere and normal:
   * environment_maps[0]; cube: the faces +X, -X, +Y, -Y, +Z, -Z (square, one size); unused: -1. */
  facet_environment_mode environment_mode;   /* default FACET_ENVIRONMENT_NONE */
  int32_t environment_maps[6];               /* facet_scene_add_texture* ids */
  float environment_strength;                /* [0, 1], default 1 */
  facet_environment_blend environment_blend; /* default FACET_ENVIRONMENT_ADD */
  int environment_dynamic;    /* cube only, non-zero: the faces are rendered from the scene every frame (maps -1) */
  int environment_resolution; /* dynamic: face size in pixels, 1..4096, default 128 */
  facet_specular_model specular_model; /* default FACET_SPECULAR_BLINN */
  /* A tangent-space normal map (docs/relief.md), lit per pixel (FACET_PHONG): -1 none (default);
   * the mesh needs uvs and tangents (facet_scene_generate_tangents). Scale: x and y of the map's
   * normals times it, |scale| <= 1e6, default 1. */
  int32_t normal_texture;
  float normal_scale;
  /* An ambient-occlusion map's red channel darkens the ambient terms by 1 + strength (r - 1), lit
   * per pixel (FACET_PHONG): -1 none (default); strength in [0, 1], default 1. */
  int32_t occlusion_texture;
  float occlusion_strength;
  /* A height map (red channel): per pixel its slopes tilt the normal like a normal map (needs the
   * mesh's tangents); flat and Gouraud with a sphere or normal environment map move its
   * coordinates. -1 none (default); |bump_scale| <= 1e6, default 1. */
  int32_t bump_texture;
  float bump_scale;
  /* Non-zero: alpha to coverage in multisampled frames (facet::Material::alpha_to_coverage): sample
   * s of N keeps its coverage when alpha > s / N; no effect at one sample. Default 0. */
  int alpha_to_coverage;
} facet_material;

typedef struct facet_fog {
  facet_fog_mode mode;
  float color[3];
  float start, end; /* linear: start <= end */
  float density;    /* exp, exp2: >= 0 */
} facet_fog;

/* Shadows of a light (facet::Shadow; docs/shadows.md), in every shading mode (flat and Gouraud:
 * modulate textures and opaque, alpha or premultiplied blending). */
typedef enum facet_shadow_method {
  FACET_SHADOW_NONE = 0,
  FACET_SHADOW_MAP = 1, /* a shadow map: spot one face, directional one fitted face, point a cube */
  FACET_SHADOW_VOLUME = 2,  /* exact per pixel: stencil shadow volumes (z-fail); no filter, no bias */
  FACET_SHADOW_RAYCAST = 3 /* exact: a shadow ray per shaded point (Intel Embree) */
} facet_shadow_method;
typedef enum facet_shadow_filter {
  FACET_SHADOW_FILTER_NONE = 0,
  FACET_SHADOW_PCF2X2 = 1,
  FACET_SHADOW_PCF3X3 = 2,
  FACET_SHADOW_PCF5X5 = 3
} facet_shadow_filter;

typedef enum facet_attenuation_model {
  FACET_ATTENUATION_GL = 0,
  FACET_ATTENUATION_LINEAR_RANGE = 1
} facet_attenuation_model;

typedef enum facet_projector_mode { FACET_PROJECTOR_MODULATE = 0, FACET_PROJECTOR_GOBO = 1 } facet_projector_mode;

typedef struct facet_light {
  facet_light_type type;
  float position[3];  /* point, spot: world space */
  float direction[3]; /* directional, spot: the way the light travels */
  float ambient[3], diffuse[3], specular[3];
  float constant_attenuation, linear_attenuation, quadratic_attenuation;
  float spot_cutoff_deg; /* spot: [0, 90] or 180 */
  float spot_exponent;
  /* Shadows; default FACET_SHADOW_NONE, resolution 2048, PCF3X3, bias constant 0, slope 0 and
   * normal 1.5. Biases in [0, 1e4], in the method's unit (facet::ShadowBias): map, the filter's
   * radius in texels at the point; raycast, 1e-4 of the casters' bounding radius; volume: none. */
  facet_shadow_method shadow_method;
  int shadow_resolution;     /* map: texels a side, [16, 16384] */
  facet_shadow_filter shadow_filter;
  float shadow_bias_constant; /* map: towards the light */
  float shadow_bias_slope;    /* map: towards the light, times tan(normal, light) */
  float shadow_bias_normal;   /* along the normal */
  int enabled;                /* default 1; a disabled light is kept but contributes nothing */
  /* point, spot: when > 0, the light provably contributes nothing beyond this distance
   * (attenuation times saturate(1 - (d / range)^4)^2); 0 = unbounded (default) */
  float range;
  /* spot: 0 (default) = GL cone (spot_cutoff_deg, spot_exponent); non-zero = smooth cone, 1 inside
   * spot_inner_deg, 0 outside spot_outer_deg, t^spot_falloff between (falloff 2 is glTF's) */
  int spot_smooth;
  float spot_inner_deg, spot_outer_deg, spot_falloff;
  /* point, spot: FACET_ATTENUATION_GL (default: the three coefficients above) or
   * FACET_ATTENUATION_LINEAR_RANGE: clamp((range_max - d + range_min) / range_max, 0, 1), with
   * 0 <= range_min <= range_max and 0 < range_max <= 1e30 (facet::AttenuationModel) */
  facet_attenuation_model attenuation_model;
  float range_min, range_max;
  /* spot: a picture the light projects (facet::Projector; lit per pixel): a facet_scene_add_texture*
   * id, or -1 (default) for none; its mode FACET_PROJECTOR_MODULATE (per channel, default) or
   * FACET_PROJECTOR_GOBO (its luminance) */
  int32_t projector_texture;
  facet_projector_mode projector_mode;
} facet_light;

typedef struct facet_camera {
  float eye[3], target[3], up[3];
  float vertical_fov_deg; /* (0, 180) */
  float near_plane, far_plane;
} facet_camera;

/* What a frame did (FrameStats in the C++ API, which documents each counter). Set struct_size to
 * sizeof(facet_frame_stats), or 0 for this version's size; a non-zero value smaller than facet
 * 0.1's struct is an error (FACET_INVALID_ARGUMENT, before anything is drawn). Counters are only ever added at the end, and
 * the library writes only those it knows: a host compiled against an older header keeps working
 * with a newer library, and one compiled against a newer header finds the further counters as it
 * initialised them. */
typedef struct facet_frame_stats {
  size_t struct_size;
  uint64_t triangles_in, triangles_drawn, vertices_lit, pixels_filled;
  double seconds_total;
  int threads;
  /* where the triangles that were not drawn went */
  uint64_t triangles_culled, triangles_clipped, triangles_outside, triangles_degenerate, triangles_small,
      triangles_nonfinite;
  uint64_t bin_entries;
  uint64_t vertices_skipped; /* vertices (flat: triangles) not lit: no drawable triangle uses them */
  uint64_t vertex_lights_evaluated, vertex_lights_skipped;
  uint64_t pixels_tested;
  /* per stage: lighting and geometry summed over objects, raster wall time, resolve summed over threads */
  double seconds_lighting, seconds_geometry, seconds_raster, seconds_resolve;
  /* shadows: the ray-cast hierarchy and the shadow maps' passes; caster triangles; the maps'
   * texels (every face) and how many of them casters wrote */
  double seconds_shadows;
  uint64_t shadow_casters, shadow_map_texels, shadow_map_pixels;
  /* added in facet 0.2 (written when struct_size reaches it): the exposure the frame used, in
   * stops (the scene's display.exposure_ev, or the metered one); 0 for GL's display */
  float exposure_ev;
  /* added in facet 0.5: preparing PBR materials' surroundings (DFG table, harmonics, prefiltered
   * cube), once per renderer and environment picture */
  double seconds_environment;
} facet_frame_stats;

typedef struct facet_renderer facet_renderer;
typedef struct facet_scene facet_scene;

typedef enum facet_viewer { FACET_VIEWER_LOCAL = 0, FACET_VIEWER_INFINITE = 1 } facet_viewer;
/* The camera pass's object order (facet::TransparentOrder): scene order (default), or opaque
 * objects first, then those with a blended material farthest first. */
typedef enum facet_transparent_order {
  FACET_TRANSPARENT_SUBMISSION = 0,
  FACET_TRANSPARENT_BACK_TO_FRONT = 1
} facet_transparent_order;

/* The library's version, "MAJOR.MINOR.PATCH" (the same as FACET_VERSION_STRING when the header
 * and the library match). */
const char* facet_version(void);

/* Defaults: Gouraud, simd path on the best ISA, back-face culling, 64-pixel tiles, all cores,
 * opaque black clear colour. Also material, light and camera defaults as in the C++ API. */
facet_render_config facet_render_config_default(void);
facet_material facet_material_default(void);
facet_light facet_light_default(void); /* directional, white, travelling along -z */
facet_camera facet_camera_default(void);

/* NULL on out of memory or an invalid configuration (then *status, if given, says why; the
 * message is not kept since there is no handle). config may be NULL for the defaults. */
facet_renderer* facet_renderer_create(const facet_render_config* config, facet_status* status);
void facet_renderer_destroy(facet_renderer* renderer); /* NULL is allowed */
const char* facet_renderer_last_error(const facet_renderer* renderer); /* "" after success */

facet_scene* facet_scene_create(void); /* an empty scene: no meshes, default camera */
void facet_scene_destroy(facet_scene* scene);
const char* facet_scene_last_error(const facet_scene* scene);

/* A triangle mesh from arrays the caller keeps: positions (3 floats per vertex), normals (3 per
 * vertex, or NULL to compute them), indices (3 per triangle). The data is copied. */
facet_status facet_scene_add_mesh(facet_scene* scene, const float* positions, size_t vertex_count,
                                  const float* normals, const uint32_t* indices, size_t triangle_count,
                                  uint32_t* mesh_id);
/* Per-vertex texture coordinates (2 floats per vertex, (0, 0) = the image's bottom-left corner) and
 * colours (3 floats per vertex in [0, 1], used as the albedo in place of the material's ambient and
 * diffuse colours) of a mesh; NULL removes them. The data is copied. */
facet_status facet_scene_set_mesh_uvs(facet_scene* scene, uint32_t mesh_id, const float* uvs);
facet_status facet_scene_set_mesh_colors(facet_scene* scene, uint32_t mesh_id, const float* rgb);
/* Tangents for normal maps: 4 floats per vertex (xyz the direction of increasing u, w = +1 or -1:
 * the bitangent is w cross(normal, xyz)); NULL removes them. Or made from the mesh's uvs by the
 * MikkTSpace algorithm (facet::generate_tangents), which may add vertices along mirrored uv seams. */
facet_status facet_scene_set_mesh_tangents(facet_scene* scene, uint32_t mesh_id, const float* xyzw);
/* Lightmap coordinates (a second uv set, 2 floats per vertex, finite; NULL removes them): where an
 * object with a lightmap (facet_scene_set_object_lightmap) reads its baked light. */
facet_status facet_scene_set_mesh_lightmap_uvs(facet_scene* scene, uint32_t mesh_id, const float* uvs);
facet_status facet_scene_generate_tangents(facet_scene* scene, uint32_t mesh_id);
/* A texture from RGBA8 texels (width x height, rows bottom first as glTexImage2D, 4 bytes per
 * texel; copied), or from a PNG or JPEG file. Sides 1..16384. */
facet_status facet_scene_add_texture_rgba8(facet_scene* scene, const uint8_t* rgba, int width, int height,
                                           facet_texture_filter filter, facet_texture_wrap wrap, uint32_t* texture_id);
facet_status facet_scene_load_texture(facet_scene* scene, const char* path, facet_texture_filter filter,
                                      facet_texture_wrap wrap, uint32_t* texture_id);
/* The same from a PNG or JPEG file's bytes in memory (copied). */
facet_status facet_scene_add_texture_encoded(facet_scene* scene, const void* bytes, size_t size,
                                             facet_texture_filter filter, facet_texture_wrap wrap, uint32_t* texture_id);

/* How a texture's colour channels encode light (facet::TextureEncoding): as stored (linear, like
 * GL_RGBA8) or sRGB, decoded to linear per texel before filtering (like GL_SRGB8_ALPHA8); alpha
 * is always linear. Textures from caller texels start linear; from files, as the file is tagged
 * (a PNG's sRGB, iCCP or gAMA chunk), else linear. Setting it rebuilds the texture's mipmaps from
 * level 0 (averaged in linear light for sRGB). */
typedef enum facet_texture_encoding { FACET_ENCODING_LINEAR = 0, FACET_ENCODING_SRGB = 1 } facet_texture_encoding;
facet_status facet_scene_set_texture_encoding(facet_scene* scene, uint32_t texture_id, facet_texture_encoding encoding);
facet_status facet_scene_texture_encoding(const facet_scene* scene, uint32_t texture_id, facet_texture_encoding* encoding);

/* The six faces of a cube environment map (+X, -X, +Y, -Y, +Z, -Z) converted from texture
 * `texture_id`, an equirectangular (latitude-longitude) picture, each face_size texels a side
 * (1..4096): new textures with ids *first_face_id .. *first_face_id + 5, bilinear and clamped to
 * the edge, for facet_material.environment_maps. The picture's centre looks along -Z, its top is
 * +Y; each face texel averages 4 x 4 bilinear reads over its footprint (docs/environment.md). */
facet_status facet_scene_add_cube_from_equirect(facet_scene* scene, uint32_t texture_id, int face_size,
                                               uint32_t* first_face_id);
/* The same, with a progress callback called after each row of a face with the share done (a
 * 4096-texel face takes minutes): return 0 to cancel (FACET_CANCELLED, the scene unchanged). Asking
 * again for the same texture, size and encoding returns the faces already made, at no cost. */
facet_status facet_scene_add_cube_from_equirect_progress(facet_scene* scene, uint32_t texture_id, int face_size,
                                                        int (*progress)(void* user, double done), void* progress_user,
                                                        uint32_t* first_face_id);

/* Replaces the scene's contents with a scene file (.json) or a model (.gltf, .glb, .obj), read
 * with a memory budget (0 = no limit). A model's missing or unreadable .mtl, texture or image
 * files are warnings (FACET_LOAD_ALLOW_MISSING, now the default, says so); with FACET_LOAD_STRICT
 * they are errors; with FACET_LOAD_FRAME a model without a camera gets one
 * that frames it at `aspect` (width / height) and a model without lights facet's default lighting
 * (the neutral studio for glTF's PBR materials, GL's rig otherwise); with FACET_LOAD_GL_MATERIALS
 * a glTF model's materials are lit with GL's model (facet --gl-materials).
 * Meshes, materials, textures, objects and lights get ids 0, 1, ... in the file's order. On
 * failure the scene is unchanged. facet_scene_warnings then lists what was read approximately
 * or not at all, one line each ("" if nothing). */
enum { FACET_LOAD_ALLOW_MISSING = 1, FACET_LOAD_FRAME = 2, FACET_LOAD_STRICT = 4, FACET_LOAD_GL_MATERIALS = 8 };
facet_status facet_scene_load_file(facet_scene* scene, const char* path, unsigned flags, float aspect,
                                   uint64_t memory_budget_bytes);
const char* facet_scene_warnings(const facet_scene* scene);
/* Which of a glTF file's cameras the next facet_scene_load_file looks through (ModelOptions::camera):
 * its index in the file's cameras ("2") or its name, or the camera's node's; NULL or "" (default)
 * the first in the scene's order. A name the file does not have fails the load, listing those it
 * has. facet_scene_cameras lists the last loaded file's cameras, one a line ("" if none). */
facet_status facet_scene_set_load_camera(facet_scene* scene, const char* camera);
const char* facet_scene_cameras(const facet_scene* scene);

/* A glTF model's animations (docs/animation.md), as the last facet_scene_load_file read them:
 * how many, and each one's name (valid until the next load) and first and last keyframe in
 * seconds. facet_scene_pose poses the model at `seconds` into `animation` (-1: the rest pose;
 * times clamp to the keys): its objects move, its skinned and morphed meshes are rewritten, the
 * file's camera and lights follow their nodes. Meshes and objects added after the load are left
 * alone; after an object or light of the model is removed it fails (load again). */
size_t facet_scene_animation_count(const facet_scene* scene);
facet_status facet_scene_animation_info(facet_scene* scene, size_t index, const char** name, double* start_s,
                                        double* end_s);
facet_status facet_scene_pose(facet_scene* scene, int animation, double seconds);
/* Which files facet_scene_load_file may read (facet/assets.hpp). By default a scene or model may
 * name files in its own folder only: no absolute path, no ".." that climbs out, no URI, no link
 * leading out. facet_scene_allow_path adds a folder whose files may be named too (NULL clears the
 * list). facet_scene_set_resolver replaces the file system: every file a load needs, the one
 * passed to facet_scene_load_file included, is asked of `resolve` by name (the naming file's
 * folder joined with the name, normalised), and facet opens no file. `resolve` returns 0 and sets
 * *bytes and *size (facet copies them before it calls `resolve` again or returns), or non-zero
 * when it has no such file. NULL `resolve` goes back to the file system. */
typedef int (*facet_resolve_fn)(void* user, const char* name, const void** bytes, size_t* size);
facet_status facet_scene_allow_path(facet_scene* scene, const char* folder);
facet_status facet_scene_set_resolver(facet_scene* scene, facet_resolve_fn resolve, void* user);
/* A camera framing every object of the scene at `aspect`, and facet's default rig of lights (a
 * headlight and a key light, ambient 0.15) added to the scene's lights. facet_scene_frame looks
 * at the model's front (glTF's convention: +Y up, the front faces +Z); the model spans 85 % of
 * the image's height or width. facet_scene_frame_view looks from `azimuth_deg` about the up axis
 * (0 the front, 90 from +X) and `elevation_deg` in (-90, 90) above the horizon, with `up`
 * FACET_UP_Z for models whose up is +Z (their front faces -Y) or another axis below, a vertical
 * field of view of `fov_deg` in (0, 180) (unused when the scene's camera is orthographic: see
 * facet_scene_set_projection), spanning `fill` in (0, 1] of the image (ViewOptions in model.hpp).
 * FACET_INVALID_ARGUMENT when the scene has no vertices to frame. */
typedef enum facet_up {
  FACET_UP_Y = 0,
  FACET_UP_Z = 1,
  /* models lying on their side or upside down (facet::UpAxis): x and -x and -y face +Z, -z faces -Y */
  FACET_UP_X = 2,
  FACET_UP_NEG_X = 3,
  FACET_UP_NEG_Y = 4,
  FACET_UP_NEG_Z = 5
} facet_up;
facet_status facet_scene_frame(facet_scene* scene, float aspect);
facet_status facet_scene_frame_view(facet_scene* scene, float aspect, float azimuth_deg, float elevation_deg,
                                    facet_up up, float fov_deg, float fill);
/* A turntable's step: the camera turned by `angle_deg` about the `up` axis through the centre of
 * the objects' box (counter-clockwise seen from above), looking at that centre from its distance;
 * with turn_lights non-zero the lights turn with it (they keep their place relative to the camera). */
facet_status facet_scene_orbit(facet_scene* scene, float angle_deg, facet_up up, int turn_lights);
facet_status facet_scene_add_default_lights(facet_scene* scene);
facet_status facet_scene_add_material(facet_scene* scene, const facet_material* material, uint32_t* material_id);
/* Per-face materials: the mesh's triangles in `group_count` consecutive runs, run g of
 * triangle_counts[g] triangles drawn with material_ids[g] by objects added with
 * facet_scene_add_object_with_mesh_materials. The counts must add up to the mesh's triangles. */
facet_status facet_scene_set_mesh_groups(facet_scene* scene, uint32_t mesh_id, const uint32_t* triangle_counts,
                                         const uint32_t* material_ids, size_t group_count);
/* model: 4x4 column-major model -> world matrix, or NULL for the identity. */
facet_status facet_scene_add_object(facet_scene* scene, uint32_t mesh_id, uint32_t material_id,
                                    const float* model, uint32_t* object_id);
/* An object drawn with its mesh's groups' materials (facet_scene_set_mesh_groups). */
facet_status facet_scene_add_object_with_mesh_materials(facet_scene* scene, uint32_t mesh_id, const float* model,
                                                        uint32_t* object_id);
/* light_id may be NULL. Object and light ids stay valid until that object or light is removed;
 * ids are not reused. */
facet_status facet_scene_add_light(facet_scene* scene, const facet_light* light, uint32_t* light_id);
facet_status facet_scene_set_light(facet_scene* scene, uint32_t light_id, const facet_light* light);
facet_status facet_scene_remove_light(facet_scene* scene, uint32_t light_id);
/* Objects: move (model: column-major, NULL = identity), change material, draw both faces (back
 * faces lit with the negated normal, not culled: glTF doubleSided), remove. */
facet_status facet_scene_set_object_transform(facet_scene* scene, uint32_t object_id, const float* model);
facet_status facet_scene_set_object_material(facet_scene* scene, uint32_t object_id, uint32_t material_id);
facet_status facet_scene_set_object_double_sided(facet_scene* scene, uint32_t object_id, int double_sided);
/* Baked light (docs/baking.md): texture_id (-1: none) read at the mesh's lightmap coordinates is
 * the light arriving at the surface, times scale (> 0); the colour is the emission plus the
 * material's diffuse colour (times its texture) times that light. FACET_LIGHTMAP_DIFFUSE: the
 * lights still add their specular term; FACET_LIGHTMAP_REPLACE: nothing else lights the object.
 * The mesh needs lightmap coordinates; rendering refuses lightmapped objects with vertex colours,
 * environment, normal or bump maps or a texture mode other than FACET_MODULATE. */
facet_status facet_scene_set_object_lightmap(facet_scene* scene, uint32_t object_id, int32_t texture_id, float scale,
                                            facet_lightmap_mode mode);
facet_status facet_scene_remove_object(facet_scene* scene, uint32_t object_id);

/* Baking (docs/baking.md): every object's lightmap, lit by the scene's lights (ray-cast shadows),
 * its emissive surfaces (area lights, soft shadows) and radiosity. Start from
 * facet_bake_config_default(). */
typedef struct facet_bake_config {
  double texels_per_unit;  /* lightmap density, texels per unit of world length (> 0; default 16) */
  int padding;             /* empty texels between charts, 1..64 (default 2) */
  int lights;              /* 1: bake the scene's lights as direct light (default); 0: only emissive surfaces */
  int radiosity;           /* 1: light bounces (default); 0: direct light only */
  int rays_per_shot;       /* default 256 */
  double small_texel;      /* a texel covering less than this share of a full one joins its fullest
                              neighbour's patch (0..1, default 0.25; 0: none) */
  int use_mesh_uvs;        /* 1 (default): an object whose mesh has lightmap coordinates (glTF TEXCOORD_1,
                              facet_scene_set_mesh_lightmap_uvs) is baked over them; 0: charts generated */
  int burial_rays;         /* probe rays per footprint piece; a piece more than half of whose rays meet
                              back faces is inside geometry and dropped (0..1024, default 16; 0: none) */
  uint64_t max_shots;      /* default 100000 */
  double residual;         /* stop when the unshot power is below this share of what entered (default 0.001) */
  int threads;             /* 0: all */
  double scale;            /* the lightmap textures hold light / scale; 0 (default): the 99.9th percentile */
  facet_lightmap_mode mode;  /* how the baked scene is drawn (default FACET_LIGHTMAP_DIFFUSE) */
  int (*progress)(void* user, double done); /* may be NULL; called at least once a second with the share of
                                               the whole bake done; return 0 to cancel (FACET_CANCELLED) */
  void* progress_user;
  double max_seconds;      /* 0 (default): no limit; radiosity stops at it, an earlier phase fails (FACET_CANCELLED) */
  uint64_t memory_budget_bytes; /* the bake's own memory (texels, footprint pieces); 0: no limit; default 4 GiB */
} facet_bake_config;
typedef struct facet_bake_stats {
  uint64_t texels, patches, shots, rays;
  double seconds, entered, absorbed, escaped, unshot, scale;
  uint64_t buried; /* footprint pieces dropped as inside geometry */
  uint64_t merged; /* small texels joined to a neighbour's patch */
} facet_bake_stats;
facet_bake_config facet_bake_config_default(void);
/* Bakes the scene and draws the result in it: each object gets its own copy of its mesh split along
 * its lightmap's charts, its lightmap as a texture and facet_scene_set_object_lightmap's settings
 * (object and mesh ids stay valid; new meshes and textures are added). stats may be NULL. On an
 * error (a density over the budget: FACET_OUT_OF_MEMORY, with the density that fits in the message)
 * the scene is unchanged. */
facet_status facet_scene_bake(facet_scene* scene, const facet_bake_config* config, facet_bake_stats* stats);
/* Materials: change one (objects using it see the change), or remove one no object or mesh group
 * uses (its id is not reused). */
facet_status facet_scene_set_material(facet_scene* scene, uint32_t material_id, const facet_material* material);
facet_status facet_scene_remove_material(facet_scene* scene, uint32_t material_id);
/* Fields by name: every material and light field of the field table (docs/scene-format.md,
 * "Material fields" and "Light fields"; the scene file's keys, dotted below an object:
 * "diffuse", "environment.strength", "shadow.bias.slope"), as doubles: a colour or vector its
 * components, a choice the index of its name in `choices`, a boolean 0 or 1, a texture its id or
 * -1 (none). A field added to the table reaches C through these, with no change to
 * facet_material or facet_light. `count` must equal the field's components. A set is checked as
 * facet_scene_set_material / facet_scene_set_light check a whole one (range, the rules between
 * fields, the scene's limits); on an error nothing changes. */
typedef struct facet_field_info {
  const char* name;
  const char* type; /* "number", "integer", "boolean", "choice", "colour", "vector" or "texture" */
  int components;
  double lo, hi;    /* number, integer, vector: each value's accepted range */
  double also;      /* number: one more accepted value outside [lo, hi], or NaN */
  const char* const* choices; /* choice: the names, in index order */
  size_t choice_count;
  const char* doc;  /* one line: what the field does */
} facet_field_info;
size_t facet_material_field_count(void);
size_t facet_light_field_count(void);
facet_status facet_material_field_info(size_t index, facet_field_info* info);
facet_status facet_light_field_info(size_t index, facet_field_info* info);
facet_status facet_scene_set_material_field(facet_scene* scene, uint32_t material_id, const char* name,
                                            const double* values, size_t count);
facet_status facet_scene_get_material_field(const facet_scene* scene, uint32_t material_id, const char* name,
                                            double* values, size_t count);
facet_status facet_scene_set_light_field(facet_scene* scene, uint32_t light_id, const char* name, const double* values,
                                         size_t count);
facet_status facet_scene_get_light_field(const facet_scene* scene, uint32_t light_id, const char* name, double* values,
                                         size_t count);
/* Scene-wide switches: two-sided lighting for every object (default 0); the specular half-vector
 * of a local (default) or infinite viewer (GL_LIGHT_MODEL_LOCAL_VIEWER). */
facet_status facet_scene_set_two_sided(facet_scene* scene, int two_sided);
facet_status facet_scene_set_viewer(facet_scene* scene, facet_viewer viewer);
/* The order the camera draws objects in (default FACET_TRANSPARENT_SUBMISSION); objects keep
 * their ids whatever the order. */
facet_status facet_scene_set_transparent_order(facet_scene* scene, facet_transparent_order order);
/* Whether an object blocks shadowed lights (cast) and can be in shadow (receive); both default
 * to non-zero. */
facet_status facet_scene_set_object_shadows(facet_scene* scene, uint32_t object_id, int cast, int receive);
/* What the picture does with the scene's light (facet::Display, docs/color.md): exposure in stops
 * ([-30, 30]; the light times 2^exposure_ev), or with auto_exposure non-zero metered per frame to
 * middle grey, then a tone-mapping operator into [0, 1]. Zeroed (the default): GL's clamp. A model
 * loaded with lights in physical units gets auto exposure, and every model the neutral operator. */
typedef enum facet_tone_mapping {
  FACET_TONE_MAPPING_NONE = 0,    /* clamp (GL's) */
  FACET_TONE_MAPPING_NEUTRAL = 1, /* Khronos PBR Neutral */
  FACET_TONE_MAPPING_ACES = 2     /* Narkowicz's 2015 ACES fit */
} facet_tone_mapping;
typedef struct facet_display {
  float exposure_ev;
  int auto_exposure;
  facet_tone_mapping tone_mapping;
} facet_display;
facet_status facet_scene_set_display(facet_scene* scene, const facet_display* display);
facet_status facet_scene_get_display(const facet_scene* scene, facet_display* display);
/* What PBR materials see around them (facet::EnvironmentLight, docs/pbr.md): nothing but the
 * scene's global ambient (NONE, the default), facet's neutral studio, or an equirectangular
 * picture of radiance (Radiance .hdr, OpenEXR, PNG or JPEG from a file, read through the scene's
 * asset access; or linear RGB floats, top row first, width = 2 height), read as three.js reads
 * one; its radiance times `intensity` ([0, 1e6]), turned by rotation_deg about +Y. A model loaded
 * with FACET_LOAD_FRAME and no lights of its own gets the studio when its materials are PBR. */
typedef enum facet_surroundings {
  FACET_SURROUNDINGS_NONE = 0,
  FACET_SURROUNDINGS_STUDIO = 1,
  FACET_SURROUNDINGS_IMAGE = 2
} facet_surroundings;
facet_status facet_scene_set_environment(facet_scene* scene, facet_surroundings source, float intensity, float rotation_deg);
facet_status facet_scene_load_environment_image(facet_scene* scene, const char* path, float intensity, float rotation_deg,
                                                uint64_t memory_budget_bytes);
facet_status facet_scene_set_environment_pixels(facet_scene* scene, const float* rgb, int width, int height, float intensity,
                                                float rotation_deg);
/* Any pointer may be null. */
facet_status facet_scene_get_environment(const facet_scene* scene, facet_surroundings* source, int* width, int* height,
                                         float* intensity, float* rotation_deg);
/* What is drawn behind the model (facet::Background): the render's clear colour (COLOUR, the
 * default) or the surroundings above (ENVIRONMENT: opaque, exposed and tone-mapped with the
 * model; blending and multisampled edges meet it as they meet the clear colour), which then need a
 * source other than NONE (FACET_INVALID_ARGUMENT naming "background" at render otherwise). */
typedef enum facet_background { FACET_BACKGROUND_COLOUR = 0, FACET_BACKGROUND_ENVIRONMENT = 1 } facet_background;
facet_status facet_scene_set_background(facet_scene* scene, facet_background background);
facet_status facet_scene_get_background(const facet_scene* scene, facet_background* background);
/* Sets the camera's placement, field of view and planes; its projection (below) is kept. */
facet_status facet_scene_set_camera(facet_scene* scene, const facet_camera* camera);
/* The scene's camera (after facet_scene_frame, a load with FACET_LOAD_FRAME or an orbit). */
facet_status facet_scene_get_camera(const facet_scene* scene, facet_camera* camera);
/* The camera's projection (facet::Projection): FACET_PROJECTION_PERSPECTIVE (default: the
 * camera's vertical_fov_deg) or FACET_PROJECTION_ORTHOGRAPHIC (glOrtho's box: `half_height` scene
 * units above and below the view, half_height x aspect across, in (0, 1e30]; near_plane >= 0 and
 * a finite far_plane). The camera with the new projection must be valid (FACET_INVALID_ARGUMENT
 * otherwise, and nothing changes). facet_scene_frame and facet_scene_frame_view frame with the
 * projection the scene's camera has. A loaded glTF's orthographic camera sets it. */
typedef enum facet_projection { FACET_PROJECTION_PERSPECTIVE = 0, FACET_PROJECTION_ORTHOGRAPHIC = 1 } facet_projection;
facet_status facet_scene_set_projection(facet_scene* scene, facet_projection projection, float half_height);
facet_status facet_scene_get_projection(const facet_scene* scene, facet_projection* projection, float* half_height);
facet_status facet_scene_set_global_ambient(facet_scene* scene, const float rgb[3]);
facet_fog facet_fog_default(void); /* no fog; GL's defaults otherwise */
facet_status facet_scene_set_fog(facet_scene* scene, const facet_fog* fog);

/* Renders into the caller's buffer: width x height pixels, rows stride_bytes apart, row 0 at the
 * top unless y_up. depth (width x height floats, depth_stride_bytes apart) and stats may be NULL.
 * Everything is checked before any byte is written. */
facet_status facet_render(facet_renderer* renderer, const facet_scene* scene, void* pixels, int width, int height,
                          size_t stride_bytes, facet_pixel_format format, int y_up, float* depth,
                          size_t depth_stride_bytes, facet_frame_stats* stats);

/* Why a frame drew nothing ("every triangle is outside the view: ..."), written to `buffer`
 * (truncated to `size` bytes with its terminating zero), or "" when it filled pixels. Returns the
 * message's full length. */
size_t facet_explain_empty_frame(const facet_frame_stats* stats, char* buffer, size_t size);

#ifdef __cplusplus
}
#endif

#endif /* FACET_FACET_H */
