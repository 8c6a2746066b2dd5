// facet's Python bindings (pybind11, NumPy): the module `facet._facet`, which `facet/__init__.py`
// re-exports. Pictures come back as NumPy arrays the binding allocates (or the caller passes),
// written in place by the renderer with the GIL released; facet's errors become facet.Error with
// facet's message (file, line or JSON path, field).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <climits>
#include <cctype>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <mutex>
#include <optional>
#include <span>
#include <type_traits>
#include <cstdio>
#include <string>
#include <vector>

#include "facet/facet.hpp"
#include "py_scene.hpp"

namespace py = pybind11;

namespace {

using namespace facet;
using facet_py::PyScene;
using facet_py::raise;

template <class T>
T value_or_raise(Result<T> r) {
  if (!r.ok()) raise(r.status());
  return std::move(*r);
}

// The value of `values` whose name (facet's to_string, the names of scene files and the command
// line) is `text`; or facet.Error naming `what` and the names it knows.
template <class E>
E parse_named(const std::string& text, const char* what, std::initializer_list<E> values) {
  std::string known;
  for (const E v : values) {
    if (text == to_string(v)) return v;
    known += (known.empty() ? "" : ", ") + std::string(to_string(v));
  }
  std::string shown;  // the caller's text, short and without control characters
  for (const char c : text.substr(0, 40)) shown += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
  raise({ErrorCode::invalid_argument, what, std::string(what) + ": unknown value '" + shown + "' (expected one of " + known + ")"});
}

ShadingMode shading_of(const std::string& s) {
  return parse_named(s, "shading", {ShadingMode::flat, ShadingMode::gouraud, ShadingMode::phong});
}
LightingPath path_of(const std::string& s) {
  return parse_named(s, "path", {LightingPath::reference, LightingPath::scalar, LightingPath::simd});
}
UpAxis up_of(const std::string& s) {
  return parse_named(s, "up", {UpAxis::y, UpAxis::z, UpAxis::x, UpAxis::neg_x, UpAxis::neg_y, UpAxis::neg_z});
}
Projection projection_of(const std::string& s) {
  return parse_named(s, "projection", {Projection::perspective, Projection::orthographic});
}
// Where a framing camera looks from (facet render's --view, --up, --fov, --projection).
ViewOptions view_of(std::array<float, 2> view, const std::string& up, float fov_deg, const std::string& projection, float fill) {
  ViewOptions v;
  v.azimuth_deg = view[0], v.elevation_deg = view[1];
  v.up = up_of(up);
  v.vertical_fov_deg = fov_deg;
  v.projection = projection_of(projection);
  v.fill = fill;
  if (Status st = validate_view(v); !st.ok()) raise(st);
  return v;
}
Isa isa_of(const std::string& s) { return parse_named(s, "isa", {Isa::best, Isa::sse2, Isa::avx2, Isa::avx512}); }
PowTier pow_of(const std::string& s) {
  return parse_named(s, "pow", {PowTier::automatic, PowTier::exact, PowTier::fast, PowTier::integer, PowTier::schlick});
}

py::dict stats_dict(const FrameStats& s) {
  py::dict d;
  d["triangles_in"] = s.triangles_in;
  d["triangles_drawn"] = s.triangles_drawn;
  d["triangles_culled"] = s.triangles_culled;
  d["triangles_clipped"] = s.triangles_clipped;
  d["triangles_outside"] = s.triangles_outside;
  d["vertices_lit"] = s.vertices_lit;
  d["vertex_lights_evaluated"] = s.vertex_lights_evaluated;
  d["pixels_tested"] = s.pixels_tested;
  d["pixels_filled"] = s.pixels_filled;
  d["seconds_lighting"] = s.seconds_lighting;
  d["seconds_geometry"] = s.seconds_geometry;
  d["seconds_raster"] = s.seconds_raster;
  d["seconds_shadows"] = s.seconds_shadows;
  d["seconds_environment"] = s.seconds_environment;
  d["seconds_total"] = s.seconds_total;
  d["exposure_ev"] = s.exposure_ev;
  d["threads"] = s.threads;
  return d;
}

// What `facet render FILE` draws: a scene file as it is (a file that imports models and has no
// camera or lights gets them as the loader says); a model with its own camera and lights, or
// framed for the image's aspect and lit by facet's default rig; no path: the built-in scene.
// A model (.gltf, .glb, .obj, any case) rather than a scene file: load_model reads it.
bool is_model_file(const std::string& path) {
  std::string ext = path;
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  auto ends = [&](const char* e) { return ext.size() >= std::strlen(e) && ext.compare(ext.size() - std::strlen(e), std::string::npos, e) == 0; };
  return ends(".gltf") || ends(".glb") || ends(".obj");
}

// `camera`: a glTF file's camera (ModelOptions::camera); `view`: frame the model with it even
// when the file has a camera (facet render --view, --fov, --projection); `cameras`: the file's.
Scene load_for_render(const std::optional<std::string>& path, float aspect, const std::vector<std::string>& allow_paths,
                      bool strict = false, std::vector<std::string>* warnings = nullptr, const std::string& camera = "",
                      const ViewOptions& framing = {}, bool reframe = false, std::vector<std::string>* cameras = nullptr,
                      bool gl_materials = false, PyScene* motion = nullptr) {
  if (!path) {
    if (!camera.empty()) raise({ErrorCode::invalid_argument, "camera", "camera: picks one of a glTF file's cameras; no file was given"});
    Scene s = make_default_scene();
    if (reframe) s.camera = value_or_raise(frame_scene(s, aspect, framing));
    return s;
  }
  if (is_model_file(*path)) {
    ModelOptions mo;
    mo.assets.allowed_roots = allow_paths;
    mo.allow_missing = !strict;
    mo.camera = camera;
    mo.gl_materials = gl_materials;
    Model m = value_or_raise(load_model(*path, mo));
    if (warnings) *warnings = m.warnings;
    if (cameras) *cameras = m.cameras;
    if (motion) motion->rig = m.rig, motion->motion = m.motion, motion->file_camera = m.has_camera && !reframe;
    if (!m.has_camera || reframe) m.scene.camera = value_or_raise(frame_scene(m.scene, aspect, framing));
    if (!m.has_lights) add_default_lights(m.scene);
    return std::move(m.scene);
  }
  if (!camera.empty()) raise({ErrorCode::invalid_argument, "camera", "camera: picks one of a glTF file's cameras; this is a scene file"});
  LoadOptions lo;
  lo.assets.allowed_roots = allow_paths;
  lo.frame_aspect = aspect;
  lo.strict = strict;
  lo.gl_materials = gl_materials;
  lo.view = framing;
  if (warnings) lo.warning = [warnings](const std::string& w) { warnings->push_back(w); };
  Scene s = value_or_raise(load_scene_file(*path, lo));
  if (reframe) s.camera = value_or_raise(frame_scene(s, aspect, framing));
  return s;
}

// A Python facet.Scene. Renderer.render draws it with the GIL released, so no other Python thread
// may change it meanwhile: while any render of it is under way, every call that changes it raises
// facet.Error (code "invalid_argument", field "scene"). `rendering` is read and written only with
// the GIL held.

// The values of a NumPy array of any real dtype as `T`, refusing any that does not convert exactly
// (a fraction, NaN, or outside [lo, hi]): NumPy's own cast would wrap 2^32 + 1 to 1, truncate
// 2.5 to 2 and turn NaN into 0 in silence.
template <class T>
std::vector<T> exact_values(const py::array& a, const char* field, double lo, double hi) {
  const char kind = a.dtype().kind();
  if (kind != 'u' && kind != 'i' && kind != 'f' && kind != 'b') {
    raise({ErrorCode::invalid_argument, field, std::string(field) + ": expected an array of numbers"});
  }
  // Integers through int64 / uint64 (exact), floats through float64 (exact for every float dtype).
  std::vector<T> out(static_cast<std::size_t>(a.size()));
  auto check = [&](auto values) {
    const auto* v = values.data();
    for (std::size_t i = 0; i < out.size(); ++i) {
      const auto x = v[i];
      const double d = static_cast<double>(x);
      bool exact = d >= lo && d <= hi;
      if constexpr (std::is_floating_point_v<std::remove_cv_t<std::remove_reference_t<decltype(x)>>>) exact = exact && std::floor(x) == x;
      if (!exact) {
        char buf[64];
        const auto shortest = std::to_chars(buf, buf + sizeof buf, d);  // the shortest text that reads back as d
        raise({ErrorCode::invalid_argument, field,
               std::string(field) + ": element " + std::to_string(i) + " is " + std::string(buf, shortest.ptr) + ", not an integer in [" +
                   std::to_string(static_cast<long long>(lo)) + ", " + std::to_string(static_cast<long long>(hi)) + "]"});
      }
      out[i] = static_cast<T>(x);
    }
  };
  if (kind == 'u' || kind == 'b') {
    check(py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>(a));
  } else if (kind == 'i') {
    check(py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>(a));
  } else {
    check(py::array_t<double, py::array::c_style | py::array::forcecast>(a));
  }
  return out;
}

class PyRenderer {
 public:
  PyRenderer(const std::string& shading, const std::string& path, const std::string& isa, const std::string& pow, int threads,
             int msaa, bool srgb, std::array<float, 4> clear, const std::string& pixel_precision) {
    RenderOptions o;
    // "auto": per scene, Phong for a loaded model (lit per pixel, as a viewer lights it), Gouraud
    // otherwise (facet render's default).
    auto_shading_ = shading == "auto";
    o.shading = auto_shading_ ? ShadingMode::gouraud : shading_of(shading);
    o.path = path_of(path);
    o.isa = isa_of(isa);
    o.pow_tier = pow_of(pow);
    o.pixel_precision = parse_named(pixel_precision, "pixel_precision", {PixelPrecision::automatic, PixelPrecision::exact, PixelPrecision::fast});
    o.threads = threads;
    o.samples = msaa;
    o.srgb = srgb;
    o.clear_color = clear;
    if (Status s = check_render_options(o); !s.ok()) raise(s);
    options_ = o;
    renderer_ = Renderer(o);
  }

  // Into `out` (H x W x 4, uint8 or float32, rows may be strided, pixels contiguous) or a new
  // array of `dtype`.
  py::array render(PyScene& scene, int width, int height, const std::string& dtype, std::optional<py::array> out) {
    if (width < 1 || height < 1) raise({ErrorCode::invalid_argument, "width", "width and height: expected at least 1"});
    const bool f32 = dtype == "float32";
    if (!f32 && dtype != "uint8") raise({ErrorCode::invalid_argument, "dtype", "dtype: expected 'uint8' or 'float32', found '" + dtype + "'"});
    py::array image;
    if (out) {
      image = *out;
      const bool u8 = py::isinstance<py::array_t<std::uint8_t>>(image) && image.dtype().is(py::dtype::of<std::uint8_t>());
      const bool fl = image.dtype().is(py::dtype::of<float>());
      if (!(u8 || fl)) raise({ErrorCode::invalid_argument, "out", "out: expected a uint8 or float32 array"});
      if (image.ndim() != 3 || image.shape(0) != height || image.shape(1) != width || image.shape(2) != 4) {
        raise({ErrorCode::invalid_argument, "out", "out: expected shape (" + std::to_string(height) + ", " + std::to_string(width) + ", 4)"});
      }
      const py::ssize_t item = fl ? 4 : 1;
      if (image.strides(2) != item || image.strides(1) != 4 * item || image.strides(0) < 4 * item * width) {
        raise({ErrorCode::invalid_argument, "out", "out: each row's pixels must be contiguous (RGBA, then the next pixel)"});
      }
      if (!image.writeable()) raise({ErrorCode::invalid_argument, "out", "out: the array is read-only"});
      return draw(scene, width, height, fl, image);  // the array's type, whatever dtype says
    }
    if (f32) {
      image = py::array_t<float>({py::ssize_t(height), py::ssize_t(width), py::ssize_t(4)});
    } else {
      image = py::array_t<std::uint8_t>({py::ssize_t(height), py::ssize_t(width), py::ssize_t(4)});
    }
    return draw(scene, width, height, f32, image);
  }

  py::dict last_stats() {
    FrameStats stats;
    {
      py::gil_scoped_release release;
      const std::lock_guard<std::mutex> lock(busy_);
      stats = renderer_.last_stats();
    }
    return stats_dict(stats);
  }

 private:
  py::array draw(PyScene& scene, int width, int height, bool f32, py::array& image) {
    ImageView view{image.mutable_data(), width, height, static_cast<std::size_t>(image.strides(0)),
                   f32 ? PixelFormat::rgba32f : PixelFormat::rgba8, false};
    Status s;
    {
      // The scene may not change while the GIL is released (PyScene::edit); counted with the GIL
      // held, on the way in and out.
      struct Rendering {
        PyScene& scene;
        explicit Rendering(PyScene& sc) : scene(sc) { ++scene.rendering; }
        ~Rendering() { --scene.rendering; }
      } rendering(scene);
      {
        py::gil_scoped_release release;  // other Python threads run while this one renders
        const std::lock_guard<std::mutex> one_frame_at_a_time(busy_);  // a renderer draws one frame at a time
        RenderOptions o = options_;
        if (auto_shading_) o.shading = scene.model ? ShadingMode::phong : ShadingMode::gouraud;
        s = renderer_.render(scene.scene, o, view);
      }
    }
    if (!s.ok()) raise(s);
    return image;
  }

  Renderer renderer_;
  RenderOptions options_;
  bool auto_shading_ = false;
  std::mutex busy_;
};

py::dict light(const std::optional<std::string>& path, const std::string& lighting_path, const std::string& isa, const std::string& pow,
               int threads, double seconds, const std::vector<std::string>& allow_paths) {
  const Scene scene = load_for_render(path, 16.0f / 9.0f, allow_paths);
  LightingOptions o;
  o.path = path_of(lighting_path);
  o.isa = isa_of(isa);
  o.pow_tier = pow_of(pow);
  o.threads = threads;
  std::uint64_t vertices = 0, lights_evaluated = 0, rounds = 0;
  VertexColors colors;
  double elapsed = 0;
  {
    py::gil_scoped_release release;
    Lighter lighter;  // threads and working memory kept over the rounds
    const auto start = std::chrono::steady_clock::now();
    do {
      for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        if (Status s = lighter.light_instance(scene, i, o, colors); !s.ok()) {
          py::gil_scoped_acquire again;
          raise(s);
        }
        const std::uint64_t n = scene.meshes[scene.objects[i].mesh].mesh.positions.size();
        vertices += n;
        lights_evaluated += n * scene.lights.size();
      }
      ++rounds;
      elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } while (elapsed < seconds);
  }
  py::dict d;
  d["path"] = to_string(o.path);
  d["isa"] = o.path == LightingPath::simd ? to_string(o.isa == Isa::best ? best_isa() : o.isa) : "none";
  d["pow"] = to_string(o.pow_tier);
  d["threads"] = threads;
  d["rounds"] = rounds;
  d["vertices"] = vertices;
  d["seconds"] = elapsed;
  d["vertices_per_second"] = elapsed > 0 ? double(vertices) / elapsed : 0.0;
  d["vertex_lights_per_second"] = elapsed > 0 ? double(lights_evaluated) / elapsed : 0.0;
  return d;
}

}  // namespace

PYBIND11_MODULE(_facet, m) {
  m.doc() = "facet: a CPU renderer (rasterizer, lighting, baked light); pictures as NumPy arrays";
  m.attr("Error") = py::reinterpret_steal<py::object>(PyErr_NewException("facet.Error", PyExc_RuntimeError, nullptr));
  m.attr("__version__") = version();
  m.def("best_isa", [] { return std::string(to_string(best_isa())); }, "The widest instruction set of this CPU facet uses.");

  py::class_<PyScene> scene_class(m, "Scene", "A scene: meshes, materials, objects, lights and a camera.");
  scene_class
      .def(py::init([](bool empty) {
             PyScene ps;
             ps.scene = empty ? Scene{} : make_default_scene();
             return ps;
           }), py::arg("empty") = false,
           "The built-in scene, or with empty=True a scene with nothing in it (build it with add_mesh, add_material, "
           "add_object and add_light).")
      .def("add_mesh", [](PyScene& ps, py::array_t<float, py::array::c_style | py::array::forcecast> positions,
                          py::array triangles,
                          std::optional<py::array_t<float, py::array::c_style | py::array::forcecast>> normals,
                          std::optional<py::array_t<float, py::array::c_style | py::array::forcecast>> uvs, const std::string& name) {
        Scene& s = ps.edit();
        if (positions.ndim() != 2 || positions.shape(1) != 3) raise({ErrorCode::invalid_argument, "positions", "positions: expected an N x 3 array"});
        if (triangles.ndim() != 2 || triangles.shape(1) != 3) raise({ErrorCode::invalid_argument, "triangles", "triangles: expected an M x 3 array"});
        const std::size_t n = static_cast<std::size_t>(positions.shape(0));
        // The library draws nothing of a triangle with a non-finite vertex, and says so only in
        // FrameStats: an array with NaN or infinity (a division by zero upstream) is refused here.
        const auto finite_rows = [](const float* v, std::size_t rows, std::size_t width, const char* what) {
          for (std::size_t i = 0; i < rows * width; ++i) {
            if (!std::isfinite(v[i])) {
              raise({ErrorCode::invalid_argument, what, std::string(what) + "[" + std::to_string(i / width) + "]: " +
                                                        (std::isnan(v[i]) ? "NaN" : "an infinity") + ", expected finite numbers"});
            }
          }
        };
        finite_rows(positions.data(), n, 3, "positions");
        if (normals && normals->ndim() == 2 && normals->shape(1) == 3) finite_rows(normals->data(), static_cast<std::size_t>(normals->shape(0)), 3, "normals");
        if (uvs && uvs->ndim() == 2 && uvs->shape(1) == 2) finite_rows(uvs->data(), static_cast<std::size_t>(uvs->shape(0)), 2, "uvs");
        const std::vector<std::uint32_t> indices = exact_values<std::uint32_t>(triangles, "triangles", 0, 4294967295.0);
        std::span<const float> normal_span;
        if (normals) {
          if (normals->ndim() != 2 || normals->shape(1) != 3 || normals->shape(0) != positions.shape(0)) {
            raise({ErrorCode::invalid_argument, "normals", "normals: expected an N x 3 array, N the number of positions"});
          }
          normal_span = {normals->data(), static_cast<std::size_t>(normals->size())};
        }
        if (uvs && (uvs->ndim() != 2 || uvs->shape(1) != 2 || uvs->shape(0) != positions.shape(0))) {
          raise({ErrorCode::invalid_argument, "uvs", "uvs: expected an N x 2 array, N the number of positions"});
        }
        // With texture coordinates and no normals: the coordinates are set before the normals are
        // computed, which may split vertices along creases and carries them along.
        const std::vector<float> flat(uvs && !normals ? 3 * n : 0, 0.0f);
        Mesh mesh = value_or_raise(mesh_from_arrays({positions.data(), static_cast<std::size_t>(positions.size())},
                                                    uvs && !normals ? std::span<const float>(flat) : normal_span,
                                                    indices));
        if (uvs) {
          mesh.uvs.resize(n);
          for (std::size_t i = 0; i < n; ++i) mesh.uvs[i] = Vec2(uvs->at(i, 0), uvs->at(i, 1));
          if (!normals) compute_vertex_normals(mesh);
          if (Status st = validate_mesh(mesh, "uvs"); !st.ok()) raise(st);
        }
        s.meshes.push_back({name.empty() ? "mesh" + std::to_string(s.meshes.size()) : name, std::move(mesh)});
        return s.meshes.size() - 1;
      }, py::arg("positions"), py::arg("triangles"), py::arg("normals") = py::none(), py::arg("uvs") = py::none(),
         py::arg("name") = "",
         "A mesh from an N x 3 array of positions and an M x 3 array of counter-clockwise triangles (vertex indices); "
         "normals computed when not given; texture coordinates from an N x 2 array. Returns its index.")
      .def("add_texture", [](PyScene& ps, py::array pixels,
                             const std::string& filter, const std::string& wrap, const std::string& encoding, const std::string& name) {
        Scene& s = ps.edit();
        if (pixels.ndim() != 3 || pixels.shape(2) != 4) {
          raise({ErrorCode::invalid_argument, "pixels", "pixels: expected an H x W x 4 array of RGBA bytes (top row first)"});
        }
        const std::vector<std::uint8_t> bytes = exact_values<std::uint8_t>(pixels, "pixels", 0, 255);
        TextureOptions o;
        o.filter = parse_named(filter, "filter", {TextureFilter::nearest, TextureFilter::bilinear, TextureFilter::trilinear});
        o.wrap = parse_named(wrap, "wrap", {TextureWrap::repeat, TextureWrap::clamp, TextureWrap::mirror});
        o.encoding = parse_named(encoding, "encoding", {TextureEncoding::linear, TextureEncoding::srgb});
        const int h = static_cast<int>(std::min<py::ssize_t>(pixels.shape(0), INT32_MAX));
        const int w = static_cast<int>(std::min<py::ssize_t>(pixels.shape(1), INT32_MAX));
        Texture t = value_or_raise(make_texture(name.empty() ? "texture" + std::to_string(s.textures.size()) : name, w, h,
                                                bytes, o));
        s.textures.push_back(std::move(t));
        return s.textures.size() - 1;
      }, py::arg("pixels"), py::arg("filter") = "trilinear", py::arg("wrap") = "repeat", py::arg("encoding") = "linear",
         py::arg("name") = "",
         "A texture from an H x W x 4 array of RGBA bytes, top row first (an image as NumPy holds it): filter nearest, "
         "bilinear or trilinear (mipmapped), wrap repeat, clamp or mirror, encoding linear or srgb. Returns its index.")
      .def("set_fog", [](PyScene& ps, const std::string& mode, std::array<float, 3> color, float start, float end, float density) {
        Scene& s = ps.edit();
        Fog fog;
        fog.mode = parse_named(mode, "mode", {FogMode::none, FogMode::linear, FogMode::exp, FogMode::exp2});
        fog.color = Color3(color[0], color[1], color[2]);
        fog.start = start, fog.end = end, fog.density = density;
        if (Status st = validate_fog(fog); !st.ok()) raise(st);
        s.fog = fog;
      }, py::arg("mode") = "linear", py::arg("color") = std::array<float, 3>{0.5f, 0.5f, 0.5f}, py::arg("start") = 0.0f,
         py::arg("end") = 1.0f, py::arg("density") = 1.0f,
         "GL's fog on the eye-space depth: none, linear (from start to end), exp or exp2 (density).")
      .def("add_material", [](PyScene& ps, std::array<float, 3> diffuse, std::array<float, 3> ambient, std::array<float, 3> specular,
                              float shininess, std::array<float, 3> emissive, float alpha, const std::string& name,
                              std::optional<std::size_t> texture, const std::string& texture_mode, std::optional<std::string> blend,
                              float alpha_cutoff, std::array<float, 2> uv_scale) {
        Scene& s = ps.edit();
        Material mat;
        mat.name = name.empty() ? "material" + std::to_string(s.materials.size()) : name;
        mat.diffuse = Color3(diffuse[0], diffuse[1], diffuse[2]);
        mat.ambient = Color3(ambient[0], ambient[1], ambient[2]);
        mat.specular = Color3(specular[0], specular[1], specular[2]);
        mat.shininess = shininess;
        mat.emissive = Color3(emissive[0], emissive[1], emissive[2]);
        mat.alpha = alpha;
        if (alpha < 1.0f) mat.blend = BlendMode::alpha;
        if (blend) {
          mat.blend = parse_named(*blend, "blend", {BlendMode::opaque, BlendMode::alpha, BlendMode::premultiplied, BlendMode::add,
                                                     BlendMode::multiply, BlendMode::subtract});
        }
        if (texture) {
          if (*texture >= s.textures.size()) raise({ErrorCode::invalid_argument, "texture", "texture: no texture " + std::to_string(*texture)});
          mat.diffuse_texture = static_cast<std::int32_t>(*texture);
        }
        mat.texture_mode = parse_named(texture_mode, "texture_mode", {TextureMode::modulate, TextureMode::replace, TextureMode::decal, TextureMode::add});
        mat.alpha_cutoff = alpha_cutoff;
        mat.uv_scale = Vec2(uv_scale[0], uv_scale[1]);
        if (Status st = validate_material(mat, s.materials.size()); !st.ok()) raise(st);
        s.materials.push_back(std::move(mat));
        return s.materials.size() - 1;
      }, py::arg("diffuse") = std::array<float, 3>{0.8f, 0.8f, 0.8f}, py::arg("ambient") = std::array<float, 3>{0.2f, 0.2f, 0.2f},
         py::arg("specular") = std::array<float, 3>{0, 0, 0}, py::arg("shininess") = 0.0f,
         py::arg("emissive") = std::array<float, 3>{0, 0, 0}, py::arg("alpha") = 1.0f, py::arg("name") = "",
         py::arg("texture") = py::none(), py::arg("texture_mode") = "modulate", py::arg("blend") = py::none(),
         py::arg("alpha_cutoff") = 0.0f, py::arg("uv_scale") = std::array<float, 2>{1.0f, 1.0f},
         "A material of the lighting model (colours in [0, 1]; alpha < 1 blends unless blend says otherwise), with an "
         "optional diffuse texture (an index from add_texture) applied by texture_mode (modulate, replace, decal, add), "
         "a blend mode (opaque, alpha, premultiplied, add, multiply, subtract), an alpha test (alpha_cutoff) and a "
         "scale of the texture coordinates. Returns its index.")
      .def("add_object", [](PyScene& ps, std::size_t mesh, std::size_t material,
                            std::optional<py::array_t<float, py::array::c_style | py::array::forcecast>> transform) {
        Scene& s = ps.edit();
        if (mesh >= s.meshes.size()) raise({ErrorCode::invalid_argument, "mesh", "mesh: no mesh " + std::to_string(mesh)});
        if (material >= s.materials.size()) raise({ErrorCode::invalid_argument, "material", "material: no material " + std::to_string(material)});
        Instance inst;
        inst.mesh = static_cast<std::uint32_t>(mesh), inst.material = static_cast<std::uint32_t>(material);
        if (transform) {
          if (transform->ndim() != 2 || transform->shape(0) != 4 || transform->shape(1) != 4) {
            raise({ErrorCode::invalid_argument, "transform", "transform: expected a 4 x 4 array (row-major, model to world)"});
          }
          for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) inst.model(r, c) = transform->at(r, c);
        }
        s.objects.push_back(inst);
        if (Status st = validate_scene(s); !st.ok()) {
          s.objects.pop_back();
          raise(st);
        }
        return s.objects.size() - 1;
      }, py::arg("mesh"), py::arg("material"), py::arg("transform") = py::none(),
         "An object drawing mesh with material, placed by a 4 x 4 transform (default: identity). Returns its index.")
      .def("add_light", [](PyScene& ps, const std::string& type, std::array<float, 3> position, std::array<float, 3> direction,
                           std::array<float, 3> diffuse, std::array<float, 3> specular, std::array<float, 3> ambient,
                           std::array<float, 3> attenuation, float spot_cutoff_deg, float spot_exponent) {
        Scene& s = ps.edit();
        Light l;
        // Light types have no to_string: the scene file's names.
        if (type == "directional") {
          l.type = LightType::directional;
        } else if (type == "point") {
          l.type = LightType::point;
        } else if (type == "spot") {
          l.type = LightType::spot;
        } else {
          raise({ErrorCode::invalid_argument, "type", "type: unknown value '" + type + "' (expected one of directional, point, spot)"});
        }
        l.position = Vec3(position[0], position[1], position[2]);
        l.direction = Vec3(direction[0], direction[1], direction[2]);
        l.diffuse = Color3(diffuse[0], diffuse[1], diffuse[2]);
        l.specular = Color3(specular[0], specular[1], specular[2]);
        l.ambient = Color3(ambient[0], ambient[1], ambient[2]);
        l.constant_attenuation = attenuation[0], l.linear_attenuation = attenuation[1], l.quadratic_attenuation = attenuation[2];
        l.spot_cutoff_deg = spot_cutoff_deg, l.spot_exponent = spot_exponent;
        if (Status st = validate_light(l, s.lights.size()); !st.ok()) raise(st);
        s.lights.push_back(l);
        return s.lights.size() - 1;
      }, py::arg("type") = "directional", py::arg("position") = std::array<float, 3>{0, 0, 0},
         py::arg("direction") = std::array<float, 3>{0, 0, -1}, py::arg("diffuse") = std::array<float, 3>{1, 1, 1},
         py::arg("specular") = std::array<float, 3>{1, 1, 1}, py::arg("ambient") = std::array<float, 3>{0, 0, 0},
         py::arg("attenuation") = std::array<float, 3>{1, 0, 0}, py::arg("spot_cutoff_deg") = 45.0f, py::arg("spot_exponent") = 0.0f,
         "A GL light: directional (direction: the way the light travels), point or spot (GL cone); attenuation = "
         "(constant, linear, quadratic). Returns its index.")
      .def("frame", [](PyScene& ps, float aspect, std::array<float, 2> view, const std::string& up, float fov_deg,
                       const std::string& projection, float fill) {
        const ViewOptions v = view_of(view, up, fov_deg, projection, fill);
        Scene& s = ps.edit();
        s.camera = value_or_raise(frame_scene(s, aspect, v));
      }, py::arg("aspect") = 16.0f / 9.0f, py::arg("view") = std::array<float, 2>{0, 0}, py::arg("up") = "y",
           py::arg("fov_deg") = 45.0f, py::arg("projection") = "perspective", py::arg("fill") = 0.85f,
           "Points the camera at every object, as facet render frames a model: from view = (azimuth, elevation) in "
           "degrees (0, 0: the front; 90, 0: from +X), the model's up axis up ('y', 'z', 'x', '-x', '-y', '-z'), a "
           "perspective camera of vertical field of view fov_deg or an orthographic one (projection='orthographic'), "
           "the model spanning `fill` of the image.")
      .def_property_readonly("object_count", [](const PyScene& ps) { return ps.scene.objects.size(); })
      .def_property_readonly("light_count", [](const PyScene& ps) { return ps.scene.lights.size(); })
      .def_property_readonly("triangle_count", [](const PyScene& ps) {
        const Scene& s = ps.scene;
        std::uint64_t n = 0;
        for (const Instance& i : s.objects) n += s.meshes[i.mesh].mesh.triangles.size();
        return n;
      })
      .def("set_camera", [](PyScene& ps, std::array<float, 3> eye, std::array<float, 3> target, std::array<float, 3> up, float fov_deg,
                            const std::string& projection, float half_height, std::optional<float> near, std::optional<float> far) {
        Camera c = ps.scene.camera;
        c.eye = Vec3(eye[0], eye[1], eye[2]), c.target = Vec3(target[0], target[1], target[2]), c.up = Vec3(up[0], up[1], up[2]);
        c.projection = projection_of(projection);
        c.vertical_fov_deg = fov_deg;
        c.half_height = half_height;
        if (near) c.near = *near;
        if (far) c.far = *far;
        if (Status st = validate_camera(c); !st.ok()) raise(st);
        ps.edit().camera = c;
      }, py::arg("eye"), py::arg("target"), py::arg("up") = std::array<float, 3>{0, 1, 0}, py::arg("fov_deg") = 45.0f,
         py::arg("projection") = "perspective", py::arg("half_height") = 1.0f, py::arg("near") = py::none(), py::arg("far") = py::none(),
         "A look-at camera: perspective with a vertical field of view fov_deg, or orthographic (glOrtho) with a box "
         "half_height scene units above and below the view; near and far planes (kept when not given; far may be "
         "float('inf') for an infinite perspective projection).")
      .def_property_readonly("camera", [](const PyScene& ps) {
        const Camera& c = ps.scene.camera;
        py::dict d;
        d["eye"] = std::array<float, 3>{c.eye.x(), c.eye.y(), c.eye.z()};
        d["target"] = std::array<float, 3>{c.target.x(), c.target.y(), c.target.z()};
        d["up"] = std::array<float, 3>{c.up.x(), c.up.y(), c.up.z()};
        d["projection"] = to_string(c.projection);
        d["fov_deg"] = c.vertical_fov_deg;
        d["half_height"] = c.half_height;
        d["near"] = c.near;
        d["far"] = c.far;
        return d;
      }, "The scene's camera, as set_camera takes it.")
      .def_property_readonly("cameras", [](const PyScene& ps) { return ps.cameras; },
                             "A loaded glTF file's cameras, one line each (facet.load's camera= picks one by index or name).")
      .def("set_display", [](PyScene& ps, py::object exposure, const std::string& tone_mapping) {
        Display d;
        if (py::isinstance<py::str>(exposure)) {
          if (exposure.cast<std::string>() != "auto") raise({ErrorCode::invalid_argument, "exposure", "exposure: expected stops or 'auto'"});
          d.automatic = true;
        } else {
          double ev = 0.0;
          try {
            ev = exposure.cast<double>();
          } catch (const py::cast_error&) {
            raise({ErrorCode::invalid_argument, "exposure", "exposure: expected stops (a number) or 'auto'"});
          }
          if (!(ev >= -30.0 && ev <= 30.0)) raise({ErrorCode::invalid_argument, "exposure", "exposure: expected stops in [-30, 30]"});
          d.ev = static_cast<float>(ev);
        }
        d.tone_mapping = parse_named(tone_mapping, "tone_mapping", {ToneMapping::none, ToneMapping::neutral, ToneMapping::aces});
        ps.edit().display = d;
      }, py::arg("exposure") = 0.0, py::arg("tone_mapping") = "none",
           "Exposure in stops (the light times 2^exposure) or 'auto' (metered to middle grey per frame), then a "
           "tone-mapping operator: none (GL's clamp), neutral (Khronos PBR Neutral) or aces. Models load with neutral, "
           "and with 'auto' when their lights are in physical units.")
      .def("set_environment", [](PyScene& ps, py::object source, float intensity, float rotation_deg) {
        EnvironmentLight e;
        if (py::isinstance<py::str>(source)) {
          const std::string name = source.cast<std::string>();
          if (name == "studio" || name == "none") {
            e.source = name == "studio" ? EnvironmentSource::studio : EnvironmentSource::none;
          } else {
            e = value_or_raise(load_environment_image(name));
          }
        } else {
          // An H x W x 3 array of linear radiance, top row first.
          const py::array_t<float, py::array::c_style | py::array::forcecast> a(source);
          if (a.ndim() != 3 || a.shape(2) != 3) raise({ErrorCode::invalid_argument, "source", "source: expected 'studio', 'none', a file name or an H x W x 3 array"});
          if (a.shape(0) > kMaxEnvironmentSide || a.shape(1) > kMaxEnvironmentSide) {
            raise({ErrorCode::invalid_argument, "source", "source: at most 16384 texels a side"});
          }
          e.source = EnvironmentSource::image;
          e.height = int(a.shape(0)), e.width = int(a.shape(1));
          e.rgb.assign(a.data(), a.data() + a.size());
          for (std::size_t i = 0; i < e.rgb.size(); ++i) {
            if (!(e.rgb[i] >= 0.0f && e.rgb[i] <= 3.4e38f)) {
              raise({ErrorCode::invalid_argument, "source", "source: texel " + std::to_string(i / 3) + " holds a negative, infinite or NaN value"});
            }
          }
        }
        e.intensity = intensity;
        e.rotation_deg = rotation_deg;
        if (Status st = validate_environment_light(e); !st.ok()) raise(st);
        ps.edit().environment_light = std::move(e);
      }, py::arg("source"), py::arg("intensity") = 1.0f, py::arg("rotation_deg") = 0.0f,
           "What PBR materials see around them: 'studio' (facet's neutral one), 'none' (the scene's global ambient), "
           "an environment picture's file name (.hdr, .exr, .png, .jpg; equirectangular) or an H x W x 3 float array "
           "of linear radiance (W = 2 H, top row first), read as three.js reads one; its radiance times intensity, "
           "turned by rotation_deg about +Y.")
      .def_property_readonly("environment", [](const PyScene& ps) {
        const EnvironmentLight& e = ps.scene.environment_light;
        py::dict d;
        d["source"] = to_string(e.source);
        d["width"] = e.width;
        d["height"] = e.height;
        d["intensity"] = e.intensity;
        d["rotation_deg"] = e.rotation_deg;
        return d;
      }, "The scene's surroundings for PBR materials, as set_environment takes them (a picture's size, not its texels).")
      .def_property("background", [](const PyScene& ps) { return std::string(to_string(ps.scene.background)); },
           [](PyScene& ps, const std::string& b) {
             if (b != "colour" && b != "color" && b != "environment") {
               raise({ErrorCode::invalid_argument, "background", "background: expected 'colour' or 'environment'"});
             }
             ps.edit().background = b == "environment" ? Background::environment : Background::colour;
           },
           "What is drawn behind the model: 'colour' (the clear colour, default) or 'environment' (the surroundings, "
           "exposed and tone-mapped with the model; needs set_environment other than 'none').")
      .def_property_readonly("warnings", [](const PyScene& ps) { return ps.warnings; },
                             "What loading read approximately or not at all, one line each (facet.load).")
      .def_property_readonly("display", [](const PyScene& ps) {
        py::dict d;
        const Display& v = ps.scene.display;
        d["exposure"] = v.automatic ? py::object(py::str("auto")) : py::object(py::float_(v.ev));
        d["tone_mapping"] = to_string(v.tone_mapping);
        return d;
      }, "The scene's exposure and tone mapping, as set_display takes them.")
      .def("orbit", [](PyScene& ps, float angle_deg, const std::string& up) {
        const UpAxis axis = up_of(up);
        if (!(std::abs(angle_deg) <= 36000.0f)) raise({ErrorCode::invalid_argument, "angle_deg", "angle_deg: expected a number in [-36000, 36000]"});
        Scene& s = ps.edit();
        const Bounds b = scene_bounds(s);
        const Vec3 centre = b.empty() ? s.camera.target : Vec3(0.5f * (b.min + b.max));
        s.camera = orbit_camera(s.camera, centre, axis, angle_deg);
      }, py::arg("angle_deg"), py::arg("up") = "y",
         "Turns the camera about the scene's centre and its up axis (y, z, x, -x, -y, -z), as facet render --orbit.");

  m.def("load", [](const std::string& path, float aspect, std::vector<std::string> allow_paths, bool strict, const std::string& camera,
                   std::optional<std::array<float, 2>> view, const std::string& up, std::optional<float> fov_deg,
                   std::optional<std::string> projection, bool gl_materials) {
    PyScene ps;
    const bool reframe = view || fov_deg || projection;
    if (reframe && !camera.empty()) {
      raise({ErrorCode::invalid_argument, "camera",
             "camera: looks through the file's camera; view, fov_deg and projection frame the model with facet's instead"});
    }
    const ViewOptions framing = view_of(view.value_or(std::array<float, 2>{0, 0}), up, fov_deg.value_or(45.0f),
                                        projection.value_or("perspective"), 0.85f);
    ps.scene = load_for_render(path, aspect, allow_paths, strict, &ps.warnings, camera, framing, reframe, &ps.cameras, gl_materials, &ps);
    ps.model = is_model_file(path);
    return ps;
  }, py::arg("path"), py::arg("aspect") = 16.0f / 9.0f, py::arg("allow_paths") = std::vector<std::string>{},
        py::arg("strict") = false, py::arg("camera") = "", py::arg("view") = py::none(), py::arg("up") = "y",
        py::arg("fov_deg") = py::none(), py::arg("projection") = py::none(), py::arg("gl_materials") = false,
        "A scene file (.json) or a model (.gltf, .glb, .obj), as facet render reads it: a model without a camera is framed "
        "for `aspect`, one without lights gets facet's default lighting (add_default_lights: the neutral studio for glTF's "
        "PBR materials, the GL rig otherwise); gl_materials=True lights glTF materials with GL's model (facet --gl-materials). Files outside the file's folder are refused unless "
        "a folder in allow_paths holds them. A missing or unreadable material library or texture is a warning "
        "(Scene.warnings) unless strict=True, which refuses the model. camera picks a glTF file's camera by index or name "
        "(Scene.cameras lists them); view=(azimuth, elevation), fov_deg or projection ('perspective', 'orthographic') "
        "frame the model with facet's camera even when the file has one; up is the model's up axis for framing.");

  py::class_<PyRenderer>(m, "Renderer", "A renderer with its own threads and options; render() releases the GIL.")
      .def(py::init<const std::string&, const std::string&, const std::string&, const std::string&, int, int, bool, std::array<float, 4>,
                    const std::string&>(),
           py::arg("shading") = "auto", py::arg("path") = "simd", py::arg("isa") = "best", py::arg("pow") = "auto",
           py::arg("threads") = 0, py::arg("msaa") = 1, py::arg("srgb") = true,
           py::arg("clear") = std::array<float, 4>{0, 0, 0, 1}, py::arg("pixel_precision") = "auto")
      .def("render", &PyRenderer::render, py::arg("scene"), py::arg("width"), py::arg("height"), py::arg("dtype") = "uint8",
           py::arg("out") = py::none(),
           "The picture as an H x W x 4 array (uint8, or float32 linear), top row first; into `out` when given.")
      .def_property_readonly("last_stats", &PyRenderer::last_stats, "What the last render did, as a dict.");

  m.def("light", &light, py::arg("path") = py::none(), py::arg("lighting_path") = "simd", py::arg("isa") = "best",
        py::arg("pow") = "auto", py::arg("threads") = 1, py::arg("seconds") = 0.5, py::arg("allow_paths") = std::vector<std::string>{},
        "Lights every vertex of the scene (or model, or the built-in scene) again and again for `seconds`: vertices lit "
        "per second on one lighting path, ISA and pow method.");
  facet_py::bind_fields(m, scene_class);
  facet_py::bind_animation(scene_class);
}
