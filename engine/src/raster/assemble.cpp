#include "raster/assemble.hpp"

#include <algorithm>
#include <atomic>
#include <utility>

namespace facet::raster {

using geometry::ClipVertex;
using geometry::ScreenVertex;

Placement place_triangle(ScreenTriangle& t, CullMode cull, bool two_sided, bool mirrored,
                         const geometry::Viewport& viewport, bool& swapped) {
  const std::int64_t area2 = signed_area2(t);
  bool back_facing = false;
  const Placement p = orient(area2, cull, two_sided, mirrored, back_facing);
  t.flags = back_facing ? ScreenTriangle::kBackFacing : 0;  // finish() adds the bitangent's flag
  if (p != Placement::placed) return p;
  return place_oriented(t, area2, viewport, swapped);
}

Placement place_oriented(ScreenTriangle& t, std::int64_t area2, const geometry::Viewport& viewport, bool& swapped) {
  swapped = area2 < 0;
  if (swapped) {  // orient clockwise on screen
    std::swap(t.x[1], t.x[2]);
    std::swap(t.y[1], t.y[2]);
    std::swap(t.z[1], t.z[2]);
    std::swap(t.inv_w[1], t.inv_w[2]);
  }
  if (!finish_setup(t, viewport.width, viewport.height, viewport.sample_lo, viewport.sample_hi)) return Placement::no_pixel;
  return Placement::placed;
}

namespace {

// A back-facing triangle of a two-sided scene is drawn with its back face's values: the back colour
// takes the front colour's place, the normal is negated (lit with -n).
void select_face(const VaryingLayout& l, float (&attr)[3][geometry::kMaxAttributes]) {
  auto move = [&l](float* a, Varying from, Varying to) {
    if (!l.has(from)) return;
    for (int c = 0; c < width_of(from); ++c) a[l.at(to) + c] = a[l.at(from) + c];
  };
  for (auto& a : attr) {
    move(a, Varying::back_color, Varying::front_color);
    move(a, Varying::back_secondary, Varying::front_secondary);
    for (const Varying v : {Varying::normal, Varying::tangent}) {
      if (!l.has(v)) continue;
      const int n = l.at(v);
      for (int c = 0; c < width_of(v); ++c) a[n + c] = -a[n + c];
    }
  }
}

class RangeAssembler {
 public:
  RangeAssembler(const AssemblyFrame& frame, const ObjectVertices& object, std::vector<ScreenTriangle>& out,
                 RangeBinning& binning)
      : frame_(frame), object_(object), out_(out), binning_(binning), counts_(binning.counts) {
    // The layout's varyings once, as (source, offset, width): gather() copies only those.
    for (int v = 0; v < kVaryingKinds; ++v) {
      const int at = object_.layout.offset[v];
      if (at >= 0) sources_[source_count_++] = {object_.varying[v], at, kVaryingWidth[v]};
    }
  }

  // Two phases (assemble.hpp): the records of triangles that can be drawn, without varyings, and
  // the marks of their vertices; then, in triangle order, their varyings, and the clipped ones.
  void place_all(const Mesh& mesh, std::size_t begin, std::size_t end, PendingTriangles& pending, std::uint8_t* drawn) {
    pending.triangle.clear();
    pending.kind.clear();
    pending.depth.clear();
    std::size_t t = begin;
    static_assert(sizeof(mesh.triangles[0]) == 3 * sizeof(std::uint32_t), "triangles are read as index triples");
    if (frame_.place && object_.screen.size() < kMaxGatheredVertices) {
      const bool cull_back = cull() == CullMode::back && !two_sided();
      const simd::PlaceParams params{frame_.viewport.width, frame_.viewport.height, cull_back,
                                     cull() == CullMode::front, object_.mirrored,
                                     frame_.viewport.sample_lo, frame_.viewport.sample_hi};
      simd::PlaceGroup group;
      for (; t + simd::kPlaceGroup <= end; t += simd::kPlaceGroup) {
        frame_.place(mesh.triangles[t].data(), object_.screen.data(), params, group);
        using Fate = simd::PlaceGroup::Fate;
        counts_.in += static_cast<std::uint64_t>(simd::kPlaceGroup - group.count[Fate::scalar]);  // place_one counts those
        counts_.nonfinite += static_cast<std::uint64_t>(group.count[Fate::nonfinite]);
        counts_.outside += static_cast<std::uint64_t>(group.count[Fate::outside]);
        counts_.culled += static_cast<std::uint64_t>(group.count[Fate::culled]);
        counts_.degenerate += static_cast<std::uint64_t>(group.count[Fate::degenerate]);
        counts_.small += static_cast<std::uint64_t>(group.count[Fate::small]);
        for (std::uint32_t keep = group.keep; keep != 0; keep &= keep - 1) {  // in lane order
          const int lane = __builtin_ctz(keep);
          take(mesh, group, lane, t + static_cast<std::size_t>(lane), pending, drawn);
        }
      }
    }
    for (; t < end; ++t) place_one(mesh, t, pending, drawn);
  }
  void finish_all(const Mesh& mesh, const PendingTriangles& pending) {
    std::uint32_t record = 0;  // the placed triangles' records come first, in order
    for (std::size_t i = 0; i < pending.triangle.size(); ++i) {
      const std::size_t t = pending.triangle[i];
      const auto& tri = mesh.triangles[t];
      set_flat(t);
      if (pending.kind[i] == PendingTriangles::clip) {
        const ScreenVertex* sv[3] = {&object_.screen[tri[0]], &object_.screen[tri[1]], &object_.screen[tri[2]]};
        clip(tri, sv[0]->guard | sv[1]->guard | sv[2]->guard);
        continue;
      }
      finish_placed(tri, out_[record], record, pending.kind[i] == PendingTriangles::placed_swapped, pending.depth[i]);
      ++record;
    }
  }

 private:
  // The placing kernel gathers 32-bit words, five a screen vertex (place.hpp).
  static constexpr std::size_t kMaxGatheredVertices = (std::size_t{1} << 31) / 5;

  // `zw`: a placed triangle's oriented z and 1/w (z0 z1 z2 w0 w1 w2), for its planes; null for a
  // clipped one.
  void keep(const Mesh& mesh, std::size_t t, PendingTriangles::Kind kind, PendingTriangles& pending,
            std::uint8_t* drawn, const std::array<float, 6>* zw = nullptr) {
    pending.triangle.push_back(static_cast<std::uint32_t>(t));
    pending.kind.push_back(kind);
    pending.depth.push_back(zw ? *zw : std::array<float, 6>{});
    if (!drawn) return;
    for (const std::uint32_t v : mesh.triangles[t]) std::atomic_ref<std::uint8_t>(drawn[v]).store(1, std::memory_order_relaxed);
  }

  // Triangle t of the mesh, the scalar twin of the placing kernel.
  void place_one(const Mesh& mesh, std::size_t t, PendingTriangles& pending, std::uint8_t* drawn) {
    ++counts_.in;
    const auto& tri = mesh.triangles[t];
    const ScreenVertex* sv[3] = {&object_.screen[tri[0]], &object_.screen[tri[1]], &object_.screen[tri[2]]};
    if (!(sv[0]->finite && sv[1]->finite && sv[2]->finite)) {
      ++counts_.nonfinite;
      return;
    }
    if (sv[0]->frustum & sv[1]->frustum & sv[2]->frustum) {
      ++counts_.outside;
      return;
    }
    if ((sv[0]->guard | sv[1]->guard | sv[2]->guard) != 0) {
      ++counts_.clipped;
      keep(mesh, t, PendingTriangles::clip, pending, drawn);
      return;
    }
    if (!(sv[0]->projected && sv[1]->projected && sv[2]->projected)) {
      ++counts_.nonfinite;
      return;
    }
    bool back_facing = false;
    const std::int64_t area2 = signed_area2(sv[0]->x, sv[0]->y, sv[1]->x, sv[1]->y, sv[2]->x, sv[2]->y);
    const Placement early = orient(area2, cull(), two_sided(), object_.mirrored, back_facing);
    if (early != Placement::placed) {
      ++(early == Placement::culled ? counts_.culled : counts_.degenerate);
      return;
    }
    ScreenTriangle& st = out_.emplace_back();
    for (int k = 0; k < 3; ++k) {
      st.x[k] = sv[k]->x, st.y[k] = sv[k]->y;
      st.z[k] = sv[k]->z, st.inv_w[k] = sv[k]->inv_w;
    }
    st.flags = back_facing ? ScreenTriangle::kBackFacing : 0;
    bool swapped = false;
    if (place_oriented(st, area2, frame_.viewport, swapped) != Placement::placed) {  // no pixel centre
      ++counts_.small;
      out_.pop_back();
      return;
    }
    const std::array<float, 6> zw = {st.z[0], st.z[1], st.z[2], st.inv_w[0], st.inv_w[1], st.inv_w[2]};
    keep(mesh, t, swapped ? PendingTriangles::placed_swapped : PendingTriangles::placed, pending, drawn, &zw);
  }

  // Lane `lane` of a placing kernel's group, triangle t, one the group keeps (the caller counted
  // the others): handed back to the scalar code, kept for clipping, or its record made.
  void take(const Mesh& mesh, const simd::PlaceGroup& g, int lane, std::size_t t, PendingTriangles& pending,
            std::uint8_t* drawn) {
    using Fate = simd::PlaceGroup::Fate;
    const auto fate = static_cast<Fate>(g.fate[lane]);
    if (fate == Fate::scalar) {
      place_one(mesh, t, pending, drawn);
      return;
    }
    if (fate == Fate::clip) {
      ++counts_.clipped;
      keep(mesh, t, PendingTriangles::clip, pending, drawn);
      return;
    }
    // The record's first cache line only: z and 1/w wait in `pending` for the planes (its last
    // line is written only where something reads it: flat colours; AssemblyFrame::place).
    ScreenTriangle& st = out_.emplace_back();
    std::array<float, 6> zw;
    for (int k = 0; k < 3; ++k) {
      st.x[k] = g.x[k][lane], st.y[k] = g.y[k][lane];
      zw[static_cast<std::size_t>(k)] = g.z[k][lane], zw[static_cast<std::size_t>(k) + 3] = g.inv_w[k][lane];
      st.bias[k] = static_cast<std::int8_t>(g.bias[k][lane]);
    }
    st.min_px = g.min_px[lane], st.min_py = g.min_py[lane];
    st.max_px = g.max_px[lane], st.max_py = g.max_py[lane];
    st.flags = g.back_facing[lane] != 0 ? ScreenTriangle::kBackFacing : 0;
    keep(mesh, t, fate == Fate::placed_swapped ? PendingTriangles::placed_swapped : PendingTriangles::placed, pending,
         drawn, &zw);
  }

  // Triangle t's flat colours (flat shading; zero otherwise).
  void set_flat(std::size_t t) {
    const Color3 none = Color3::Zero();
    flat_front_ = object_.flat_front ? object_.flat_front[t] : none;
    flat_back_ = object_.flat_back ? object_.flat_back[t] : flat_front_;
    spec_front_ = object_.flat_secondary_front ? object_.flat_secondary_front[t] : none;
    spec_back_ = object_.flat_secondary_back ? object_.flat_secondary_back[t] : spec_front_;
  }

  // A placed triangle's varyings in its on-screen vertex order, then finish().
  void finish_placed(const std::array<std::uint32_t, 3>& tri, ScreenTriangle& st, std::uint32_t index, bool swapped,
                     const std::array<float, 6>& zw) {
    const std::uint32_t order[3] = {tri[0], swapped ? tri[2] : tri[1], swapped ? tri[1] : tri[2]};
    float attr[3][geometry::kMaxAttributes];
    for (int k = 0; k < 3; ++k) gather(order[k], attr[k]);
    finish(st, index, attr, zw.data(), zw.data() + 3);
  }

  // A triangle crossing the guard band or the near or far plane: clipped in clip space, its
  // pieces projected, placed and finished.
  void clip(const std::array<std::uint32_t, 3>& tri, std::uint32_t outcodes) {
    ClipVertex v[3];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = tri[static_cast<std::size_t>(k)];
      const auto& c = object_.clip[i];
      v[k].x = c[0];
      v[k].y = c[1];
      v[k].z = c[2];
      v[k].w = c[3];
      gather(i, v[k].attr);
    }
    ClipVertex polygon[geometry::kMaxClippedVertices];
    const int count =
        geometry::clip_triangle(v[0], v[1], v[2], outcodes, frame_.planes, object_.layout.clipped, polygon);
    for (int i = 1; i + 1 < count; ++i) emit(polygon[0], polygon[i], polygon[i + 1]);
  }

  // The layout's varyings of vertex i (the first layout.clipped floats; the rest is not read).
  void gather(std::uint32_t i, float* a) const {
    for (int k = 0; k < source_count_; ++k) {
      const Source& src = sources_[k];
      const float* from = src.values + static_cast<std::size_t>(i) * static_cast<std::size_t>(src.width);
      float* to = a + src.offset;
      if (src.width == 3) {
        to[0] = from[0], to[1] = from[1], to[2] = from[2];
      } else {
        for (int c = 0; c < src.width; ++c) to[c] = from[c];
      }
    }
  }

  // The draw's culling: the frame's, or for one of a double-sided blended object's two draws its
  // faces alone (front: back faces culled, lit one-sided; back: front faces culled, lit as backs).
  CullMode cull() const { return object_.only == 1 ? CullMode::back : object_.only == 2 ? CullMode::front : frame_.cull; }
  bool two_sided() const { return object_.only == 1 ? false : object_.only == 2 ? true : frame_.two_sided || object_.two_sided; }

  bool place(ScreenTriangle& t, bool& swapped) {
    switch (place_triangle(t, cull(), two_sided(), object_.mirrored, frame_.viewport, swapped)) {
      case Placement::placed: return true;
      case Placement::degenerate: ++counts_.degenerate; return false;
      case Placement::culled: ++counts_.culled; return false;
      case Placement::no_pixel: ++counts_.small; return false;
    }
    return false;
  }

  // A placed triangle (record `index` of the range) with its varyings: its face's values, planes,
  // and its bins.
  // z and inv_w: the triangle's (oriented), from its record or from `pending`.
  void finish(ScreenTriangle& t, std::uint32_t index, float (&attr)[3][geometry::kMaxAttributes], const float* z,
              const float* inv_w) {
    const bool use_back = t.back_facing() && (frame_.two_sided || object_.two_sided);
    if (object_.flat_front) {  // flat shading: the only reader of these
      const Color3& flat = use_back ? flat_back_ : flat_front_;
      t.flat_rgb[0] = flat.x();
      t.flat_rgb[1] = flat.y();
      t.flat_rgb[2] = flat.z();
      const Color3& spec = use_back ? spec_back_ : spec_front_;
      t.flat_secondary[0] = spec.x();
      t.flat_secondary[1] = spec.y();
      t.flat_secondary[2] = spec.z();
    }
    if (use_back) select_face(object_.layout, attr);
    // The triangle's tangent frame: the sign most of its vertices carry (MikkTSpace gives one per
    // triangle), flipped with the back face (whose normal and tangent select_face negated).
    bool negative = false;
    if (object_.layout.has(Varying::tangent_sign)) {
      const int s = object_.layout.at(Varying::tangent_sign);
      negative = (attr[0][s] + attr[1][s] + attr[2][s] < 0.0f) != use_back;
    }
    t.flags = static_cast<std::uint8_t>((t.flags & ScreenTriangle::kBackFacing) | (negative ? ScreenTriangle::kBitangentNegative : 0));
    t.alpha = object_.alpha;
    t.object = object_.object;
    compute_planes(t, z, inv_w, attr, object_.layout.raster);
    bin_triangle(t, index, frame_.grid, binning_);
  }

  // A clipped piece: projected here (its vertices are new), then placed and finished.
  void emit(const ClipVertex& a, const ClipVertex& b, const ClipVertex& c) {
    const ClipVertex* v[3] = {&a, &b, &c};
    ScreenTriangle& t = out_.emplace_back();
    for (int k = 0; k < 3; ++k) {
      ScreenVertex sv{};
      if (!geometry::project(*v[k], frame_.viewport, sv)) {
        ++counts_.nonfinite;
        out_.pop_back();
        return;
      }
      t.x[k] = sv.x, t.y[k] = sv.y, t.z[k] = sv.z, t.inv_w[k] = sv.inv_w;
    }
    bool swapped = false;
    if (!place(t, swapped)) {
      out_.pop_back();
      return;
    }
    const int order[3] = {0, swapped ? 2 : 1, swapped ? 1 : 2};
    float attr[3][geometry::kMaxAttributes];
    for (int k = 0; k < 3; ++k) std::copy(v[order[k]]->attr, v[order[k]]->attr + object_.layout.clipped, attr[k]);
    finish(t, static_cast<std::uint32_t>(out_.size() - 1), attr, t.z, t.inv_w);
  }

  const AssemblyFrame& frame_;
  const ObjectVertices& object_;
  std::vector<ScreenTriangle>& out_;
  RangeBinning& binning_;
  TriangleCounts& counts_;
  struct Source {
    const float* values;
    int offset, width;
  };
  Source sources_[kVaryingKinds] = {};
  int source_count_ = 0;
  Color3 flat_front_ = Color3::Zero(), flat_back_ = Color3::Zero();
  Color3 spec_front_ = Color3::Zero(), spec_back_ = Color3::Zero();
};

}  // namespace

void assemble_range(const AssemblyFrame& frame, const Mesh& mesh, const ObjectVertices& object, std::size_t begin,
                    std::size_t end, std::vector<ScreenTriangle>& out, RangeBinning& binning, PendingTriangles& pending) {
  out.clear();
  binning.clear();
  RangeAssembler assembler(frame, object, out, binning);
  assembler.place_all(mesh, begin, end, pending, nullptr);
  assembler.finish_all(mesh, pending);
}

void place_range(const AssemblyFrame& frame, const Mesh& mesh, const ObjectVertices& object, std::size_t begin,
                 std::size_t end, std::vector<ScreenTriangle>& out, RangeBinning& binning, PendingTriangles& pending,
                 std::uint8_t* drawn) {
  out.clear();
  binning.clear();
  RangeAssembler(frame, object, out, binning).place_all(mesh, begin, end, pending, drawn);
}

void finish_range(const AssemblyFrame& frame, const Mesh& mesh, const ObjectVertices& object,
                  std::vector<ScreenTriangle>& out, RangeBinning& binning, const PendingTriangles& pending) {
  RangeAssembler(frame, object, out, binning).finish_all(mesh, pending);
}

}  // namespace facet::raster
