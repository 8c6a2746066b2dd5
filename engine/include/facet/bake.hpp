// Baked light: every object's surface cut into lightmap texels (unwrap_lightmap, world units), lit
// by the scene's lights with ray-cast shadows, then by each other through progressive-refinement
// radiosity (Cohen, Chen, Wallace & Greenberg 1988) with form factors found by casting rays
// through Embree. docs/baking.md has the method, its units and its tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "facet/lightmap.hpp"
#include "facet/mesh.hpp"
#include "facet/scene.hpp"
#include "facet/status.hpp"
#include "facet/types.hpp"

namespace facet {

struct BakeOptions {
  // The charts of every object, at texels_per_unit texels per unit of world length.
  LightmapUvOptions charts;
  // An object whose mesh brings lightmap coordinates (Mesh::lightmap_uvs, a glTF's TEXCOORD_1)
  // is baked over them (lightmap_from_mesh_uvs: a square atlas at charts.texels_per_unit on
  // average, at most charts.max_size) instead of generated charts; false: charts for every object.
  bool use_mesh_uvs = true;
  // The footprint of a texel: split into subdivisions x subdivisions squares, each clipped with
  // each triangle over it; light is evaluated at each piece's centroid and weighted by its area.
  int subdivisions = 2;
  // Pieces buried in geometry (a floor running under a wall or a block, a texel straddling a wall)
  // are found by burial_rays cosine-distributed probe rays from each piece's centroid: a piece
  // more than half of whose rays meet back faces is dropped, so that light neither leaks out of a
  // wall nor is shot into one (a texel whose pieces are all buried gets no light, and dilation
  // fills it from its neighbours). 0: no probes, every piece kept.
  int burial_rays = 16;
  // A texel whose footprint covers less than small_texel times a full texel's area (the median of
  // the object's texels; a texel at a chart's edge that a triangle barely touches) joins its
  // fullest neighbour of the same material as one patch: a small patch gets few rays and each
  // deposits much (speckle), and shows its neighbour's light instead. 0: no merging.
  double small_texel = 0.25;
  // Direct light: the diffuse term of every enabled light of the scene (GL's n.l, attenuation and
  // spot cone), each light's visibility by one ray per piece (every light casts shadows here).
  bool direct = true;
  // Emissive surfaces as area lights: their light gathered at each piece from area_samples points
  // on them (chosen by emitted power, shadow rays to each: soft shadows), instead of shot by
  // radiosity (which is noisier: a shot's rays land on few texels). Radiosity then shoots what
  // the surfaces reflect.
  bool gather_emitters = true;
  int area_samples = 64;
  // Radiosity: patches are texels; each shot sends the unshot radiosity of the patch with the most
  // unshot power along rays_per_shot rays (cosine-distributed, stratified, a fixed sequence per
  // patch and shot). Stops when the unshot power falls below `residual` times the power that
  // entered (reflected direct light, and emission unless gathered), after max_shots shots, or after
  // max_seconds (0: no limit; a time limit makes the result depend on the machine's speed).
  // max_seconds bounds the whole bake: radiosity stops at it with the light shot so far, and an
  // earlier phase (charts, patches, burial probes, direct light, emitters), which has no partial
  // result to give, fails with ErrorCode::cancelled naming the phase, within a second of it.
  bool radiosity = true;
  int rays_per_shot = 256;
  std::size_t max_shots = 100000;
  double residual = 1e-3;
  double max_seconds = 0;
  // The unshot power left at the stop, spread as an ambient term over every patch: the paper's
  // estimate (the average unshot radiosity, reflected again and again), with the share of shot
  // light that lands on a front face and the share reflected measured over the shots made (the
  // paper's 1 / (1 - average albedo) assumes a closed scene and overshoots in an open one); not
  // when that reflectance is 1 (no finite estimate).
  bool ambient_from_unshot = true;
  // Texels of all lightmaps together at most this many; refused before any work.
  std::size_t max_texels = std::size_t{1} << 24;
  // The bake's own memory (its charts' texels, footprint pieces, patches and per-piece light) at
  // most this many bytes (0: no limit): the texels are counted before any piece is made, and the
  // pieces as they are made; over it, ErrorCode::out_of_memory with the numbers (field
  // "memory_budget_bytes"). The scene itself and Embree's hierarchy are not counted.
  std::uint64_t memory_budget_bytes = kDefaultLoadBudgetBytes;
  int threads = 0;  // 0: the machine's hardware threads
  // Called on the calling thread between pieces of every phase (at least once a second while the
  // bake runs) with the share of the whole bake done, which only grows: each phase that runs
  // (charts, patches, burial probes, direct light, emitters, radiosity) takes an equal share;
  // radiosity's own share is 1 - unshot / entered power, or the share of max_shots if larger.
  // Return false to stop with ErrorCode::cancelled.
  std::function<bool(double done)> progress;
};

// One object's lightmap. light[y * width + x] (row 0 at the bottom, as uv (0, 0)): the light
// arriving at the texel in the units of a light's diffuse colour (a directional light of diffuse
// colour c, perpendicular, unshadowed, gives c), from the direct lights and from other surfaces.
// A surface's colour is its emission plus its albedo (material diffuse) times this. Texels no
// triangle touches hold the average of their neighbours (dilated `charts.padding` times), else 0.
struct BakedLightmap {
  std::uint32_t object = 0;  // index in Scene::objects
  LightmapUnwrap unwrap;     // its charts (the object's mesh in world space)
  bool mesh_uvs = false;     // the atlas is over the mesh's own lightmap coordinates (use_mesh_uvs)
  std::vector<Color3> light;
  std::vector<float> area;   // world area of each texel's footprint (0: untouched)
};

struct BakeStats {
  std::size_t texels = 0, patches = 0, pieces = 0;  // atlas texels, texels with area, footprint pieces
  std::size_t buried = 0;                            // pieces dropped as buried (not in `pieces`)
  std::size_t merged = 0;                            // small texels joined to a neighbour's patch
  std::size_t shots = 0, rays = 0;                  // radiosity shots and rays, shadow rays included
  // Power (colour units times area, summed over R, G and B): what entered the patches as unshot
  // radiosity (reflected direct light, plus the emission when it is shot rather than gathered),
  // what the patches absorbed, what left the scene, what back faces took, and what was still
  // unshot at the stop. entered = absorbed + escaped + back_faces + unshot to rounding (tested).
  double entered = 0, absorbed = 0, escaped = 0, back_faces = 0, unshot = 0;
  double seconds = 0;
  std::string stopped_by;  // "residual", "max_shots", "max_seconds", "no radiosity"
};

struct BakeResult {
  std::vector<BakedLightmap> lightmaps;  // one per object, in object order
  BakeStats stats;
};

// The same bytes for any thread count (rays and their sample sequences are fixed; their results
// are reduced in a fixed order; the Embree hierarchy is built on one thread). Errors: an invalid
// scene or option (its field), a lightmap over the budget (ErrorCode::out_of_memory, before any
// work), Embree's errors, cancellation.
Result<BakeResult> bake_lightmaps(const Scene& scene, const BakeOptions& options = {});

// The scale that maps a bake's light into 8-bit textures: the 99.9th percentile of the largest
// channel of every texel with area (a few of the brightest texels clip); 1 when nothing is lit.
double lightmap_scale(const BakeResult& result);

// Draws a bake of `scene` in it: each object gets its own copy of its mesh split along its
// charts (with_lightmap_uvs), its lightmap as an 8-bit texture of light / scale (bilinear, clamped
// to the edge, linear; named "lightmap_K"), and Instance::lightmap with `scale` and `mode`.
// `result` must come from bake_lightmaps(scene) (one lightmap per object). On an error the scene
// is unchanged.
Status apply_lightmaps(Scene& scene, const BakeResult& result, double scale, LightmapMode mode = LightmapMode::diffuse);

}  // namespace facet
