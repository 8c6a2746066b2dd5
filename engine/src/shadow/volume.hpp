// Internal: stencil shadow volumes (z-fail, "Carmack's reverse"), exact hard shadows per pixel.
//
// A frame with volume-shadowed lights first draws the camera's depth alone (a depth-only pass of
// the same tile pipeline, same view, culling and triangles as the colour pass; materials that do
// not write depth are left out). Then, per light, the casters' shadow volume is built in the
// camera's eye space, in double:
//   - a closed mesh (every edge used once each way by its triangles, vertices welded by position)
//     casts from its triangles facing away from the light (n . (L - a) < 0; a directional light:
//     n . l < 0), each turned towards the light: they are the volume's front cap, and their copies
//     pushed to infinity away from the light (w = 0) its back cap (a directional light's back cap
//     is a single point, so it has none). The silhouette is the lit side's, but the mesh's own
//     dark side is the cap, so no surface of the mesh is inside its own volume: where smooth
//     normals light a face that looks away from the light, the lighting decides (as ray-cast
//     shadows' normal offset does), while whatever lies behind the mesh is in shadow;
//   - every edge on the boundary of that set (the silhouette) is extruded to infinity as a quad
//     (two triangles), oriented outwards;
//   - a mesh that is not closed casts from both sides, as with ray-cast shadows: all its
//     triangles, each turned towards the light, and the boundary is taken of that set (the sum
//     of the triangles' oriented edges), so its open edges are extruded as well.
// Triangle adjacency is built once per mesh and kept while the mesh is unchanged.
// The volume's triangles are clipped against the near plane and the guard band (never the far
// plane: points at infinity project to finite pixels with window depth just above 1), snapped to
// the raster's fixed point and rasterized with its top-left rule (raster/triangle_setup.hpp), so
// neighbouring volume faces cover each pixel centre once. Per pixel, each volume face lying behind
// the scene's depth there adds +1 if it faces away from the camera and -1 if it faces it
// (z-fail); the pixel is in shadow when the sum is not zero. Sums of integers do not depend on
// the order of the faces, so the masks are the same for any thread count.
//
// Ties: a caster's surface is its own cap, at the same depth up to rounding (its vertices are
// transformed and snapped by the camera pass's own code, so it covers the same pixels). Within
// kDepthTolerance (window depth) of the scene's depth, a cap counts as behind when it faces the
// camera and in front when it faces away: the visible point is taken a hair off the cap along the
// cap's outward side, towards the light, outside the volume. So no surface shadows itself: a lit
// face is in front of its cap, and a closed mesh's dark side (its cap) is left to the lighting.
// An extruded silhouette contains the light's direction, which cannot separate it from the point;
// where it meets its cap at the point (the volume folding over on screen, cap and side facing
// opposite ways) it must count exactly when the cap does, so a side counts a tie when it faces
// away from the camera. The tolerance lets a receiver less than that from another caster's cap
// escape it; it is 8 float steps at depth 1.
// A shaded point (Phong pixel) finds its light's visibility in the mask at the pixel it projects
// to. Blended and alpha-tested surfaces take the visibility of the depth-writing surface behind
// them (the depth pass holds that one), as in GL's stencil shadows.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "common/parallel.hpp"
#include "geometry/project.hpp"
#include "facet/image.hpp"
#include "facet/scene.hpp"

namespace facet::shadow {

inline constexpr double kDepthTolerance = 1.0 / (1 << 20);

// A mesh's triangle adjacency: its undirected edges between welded vertices (vertices within
// kWeld of the mesh's extent of each other are one) and, per edge, the triangles that use it.
inline constexpr double kWeld = 1.0 / (1 << 20);
struct MeshEdges {
  std::vector<std::uint32_t> weld;                   // vertex -> the first vertex welded to it
  std::vector<std::array<std::uint32_t, 2>> edges;   // welded ends, a < b
  std::vector<std::uint32_t> first;                  // incident[first[e], first[e + 1]): edge e's uses
  std::vector<std::uint32_t> incident;               // triangle * 2 + 1 if the triangle runs b -> a, else + 0
  bool closed = false;  // every edge is used as often a -> b as b -> a (and there is one)
  // What it was built from (compared when the mesh may have changed).
  std::vector<Vec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;

  void build(const Mesh& mesh);
  bool built_from(const Mesh& mesh) const;
};

// One volume triangle on screen, set up: snapped vertices, window depth (unclamped), and what it
// adds behind the scene: +1 (faces away from the camera) or -1.
struct VolumeTriangle {
  std::int32_t x[3], y[3];  // oriented as raster::ScreenTriangle's (area2 > 0)
  double z[3];
  double inv_area2;
  int min_px, min_py, max_px, max_py;  // covered pixel bounds inside the frame
  std::int8_t bias[3];                 // the top-left rule's
  std::int8_t sign;
  bool side;  // a silhouette's extrusion (else a cap)
};

class ShadowVolumes {
 public:
  // Plans a frame of `width` x `height` pixels: the camera's depth image (window depth, y down),
  // and which lights cast volume shadows (enabled, shadow.method == volume).
  void plan(const Scene& scene, int width, int height);
  bool active() const { return !lights_.empty(); }
  void disable() { lights_.clear(), mask_of_.clear(); }  // no volume this frame
  DepthView depth_view();
  // Per tile of `tile_size` pixels: 1 when it may hold anything but far depth (as ShadowMap's).
  std::uint8_t* dirty_tiles(int tile_size);

  // After the depth pass: every planned light's mask, from the casters of `scene` seen through
  // `view` (world -> eye) and `projection`, in `arena`. Fails only for lack of memory.
  void build(const Scene& scene, const Eigen::Matrix4d& view, const Eigen::Matrix4d& projection,
             parallel::Arena& arena);

  // Whether scene light `light` has a mask this frame.
  bool has(std::size_t light) const;
  // visible[i] = the mask of `light` at the pixel eye-space point i projects to (1 lit, 0 in
  // shadow); points off the image or behind the camera are lit. Coordinates px[i * stride], ...
  void visibility(std::size_t light, std::size_t count, const float* px, const float* py, const float* pz,
                  std::size_t stride, float* visible) const;

  std::size_t volume_triangles() const { return volume_triangles_; }  // this frame, all lights
  // Bytes a frame of `width` x `height` with `lights` volume lights and `casters` caster
  // triangles takes, about (the depth image, the masks, the volumes' triangles).
  static std::uint64_t bytes(int width, int height, std::size_t lights, std::size_t casters);

 private:
  void build_light(const Scene& scene, const Light& light, const Eigen::Matrix4d& view);
  void rasterize(std::uint8_t* mask, parallel::Arena& arena);
  // Clips, projects and sets up volume triangle (a, b, c) of verts_ into triangles_.
  void emit(std::uint32_t a, std::uint32_t b, std::uint32_t c, bool side);

 public:
  // A volume vertex in the camera's clip space; a caster vertex inside the guard band also has
  // its snapped screen position from the camera's own transform.
  struct ClipVert {
    Eigen::Vector4d clip;
    std::int32_t x = 0, y = 0;
    bool snapped = false;
  };

 private:

  int width_ = 0, height_ = 0;
  std::vector<float> depth_;
  std::vector<std::uint8_t> dirty_;
  int dirty_tile_size_ = 0;
  std::vector<std::size_t> lights_;        // scene lights with volumes
  std::vector<int> mask_of_;               // per scene light: its mask's index, or -1
  std::vector<std::uint8_t> masks_;        // per volume light, width x height (1 lit)
  Eigen::Matrix4d projection_ = Eigen::Matrix4d::Identity();
  std::vector<MeshEdges> edges_;           // per scene mesh (built for casters only)
  std::vector<Eigen::Vector4d> eye_;       // scratch: a caster's eye-space vertices (w = 1)
  std::vector<ClipVert> verts_;            // scratch: its clip-space vertices, then their points at infinity
  std::vector<std::array<float, 4>> clip_;  // scratch: the camera pass's transform of them
  std::vector<geometry::ScreenVertex> screen_;
  geometry::ClipPlanes planes_{};
  double guard_x_ = 0, guard_y_ = 0;
  std::vector<std::int8_t> facing_;        // scratch: per triangle, +1 / -1 / 0
  std::vector<VolumeTriangle> triangles_;  // the light's volume on screen
  std::vector<std::uint32_t> band_first_, band_list_, band_cursor_;  // the volume's triangles per band of rows
  std::vector<std::int32_t> counts_;       // per thread slot: one band's sums
  std::size_t volume_triangles_ = 0;
};

}  // namespace facet::shadow
