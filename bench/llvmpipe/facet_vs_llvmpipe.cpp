// facet against Mesa's llvmpipe, on the same work in the same run: the same scene (mesh, normals,
// camera, lights, materials), rendered by OpenGL 2.1 fixed-function lighting through OSMesa
// (off-screen, into a caller buffer; Gouraud, depth test LESS, back faces culled) and by facet's
// default path with the same thread count (llvmpipe: LP_NUM_THREADS, set before the first
// context; facet: RenderOptions::threads). Reports ms per frame for each (the two take turns in
// three rounds of --seconds / 3, and each reports its median round), the ratio, and the
// image difference over the pixels either renderer drew: mean absolute difference, share
// within 2 steps, PSNR; writes both images.
//
// GL-compatible lighting: facet's model *is* GL 2.1's (emission + global ambient + per light
// attenuated ambient/diffuse/Blinn-Phong specular with h = normalize(L + V), spot cutoff and
// exponent, colour clamped per vertex, 0^0 = 1). The one default that differs is the viewer:
// facet's Scene defaults to a local viewer, GL to an infinite one; this program sets
// GL_LIGHT_MODEL_LOCAL_VIEWER from the scene, so either works. Features GL 2.1 lacks (smooth
// cones, light ranges, shininess above 128) are refused with a message.
//
// Surfaces are drawn with their GL 2.1 equivalents: textures with facet's own mip levels
// (glTexImage2D per level, so both sample the same texels), filters, wrap modes, the texture
// environment and a texture matrix for uv_scale; GL_SEPARATE_SPECULAR_COLOR for textured
// materials; vertex colours through glColorMaterial(AMBIENT_AND_DIFFUSE); blending (glBlendFunc,
// glBlendEquation for subtract), glDepthMask, the alpha test (GEQUAL) and fog. Emission after the
// texture (emissive textures, emission_after_texture) is a third texture unit under GL_ADD whose
// texels are emissive x the emissive texture's (or one texel of the emissive colour), alpha 1, with
// the material's GL emission 0: GL adds it after units 0 and 1 and before the separate specular,
// as facet does (8-bit texels of the product: half a step more than facet's float product).
// sRGB textures are GL_SRGB8_ALPHA8 (decoded per texel, then filtered); --srgb draws into a
// framebuffer object with an sRGB colour buffer and GL_FRAMEBUFFER_SRGB (blending in linear, each
// write encoded) against facet's RenderOptions::srgb.
// --shading phong lights facet per pixel (GL still per vertex: for finely tessellated scenes) and
// draws what facet applies only per pixel where GL 2.1 has an equivalent (per_pixel_incompatibility
// says when): a projector as texture unit 3 (eye-linear texgen, the light's matrix, GL_MODULATE),
// normal maps as ARB_texture_env_dot3 (the tangent-space light vector as the vertex colour).
// Environment maps are the second unit, through texgen (GL_SPHERE_MAP, GL_REFLECTION_MAP into a
// cube map with the view's inverse rotation as texture matrix, GL_NORMAL_MAP scaled to [0, 1]),
// level 0 with linear filtering clamped to the edge, the strength folded into the texels or the
// environment colour (gl_prepare); facet's flat and Gouraud shading generate the same coordinates
// at the vertices, so the two are compared per vertex. Scenes with
// surfaces are held to the surfaces target (mean <= 1 step, >= 97 % of covered pixels within 2
// steps): llvmpipe filters textures in 8-bit fixed point and chooses the LOD per 2x2 quad, facet
// in float per pixel, and both round blends differently (8-bit framebuffer against float tiles).
//
//   facet_vs_llvmpipe [--threads N] [--width W] [--height H] [--seconds S] [--out DIR] [--quick]
//                     [--check] [--rounds] [--filter TEXT] [--json FILE] [--srgb] [--shading gouraud|phong]
//                     [--with-depth] [--pixel-precision auto|exact|fast] [--msaa 1|4|8|16] [--allow-path DIR]
//                     [SCENE.json | MODEL.gltf | MODEL.glb | MODEL.obj ...]
// Scene files and models are read as `facet render` reads them (a model without a camera framed,
// one without lights given facet's default rig); a scene GL 2.1 cannot draw here is skipped with
// every reason at once. Installed beside facet (when OSMesa is there at build time); away from the
// source tree the built-in cases that need the repository's scene files are skipped.
// --pixel-precision sets facet's RenderOptions::pixel_precision (default auto, as facet renders
// by default; fast: the 16-bit tier's fixed-point texels where it has a program).
// --msaa N multisamples both: llvmpipe draws into a multisampled framebuffer object (GL_MULTISAMPLE
// on) resolved by glBlitFramebuffer every frame (in its timed frame), facet renders with
// RenderOptions::samples = N; every scene is then held to the surfaces target.
// Both sides do the same work in the timed rounds: each draws into its colour buffer and keeps
// its depth to itself (llvmpipe inside GL, facet in its tiles); the depth images the comparison
// uses are read after the timed rounds (glReadPixels; one more facet frame with a depth view).
// --with-depth times facet writing its depth view as well (a read-back llvmpipe does not pay:
// about 1-2 ms a frame at 1920x1080), as this program did before.
// --rounds prints each renderer's three timed rounds (the drift the medians leave out).
// --lights N gives scene files N of the built-in cases' lights (GL 2.1-expressible: scene files may
// use smooth cones or light ranges, which GL 2.1 lacks) and caps shininess at 128.
// --filter runs only the cases whose name contains TEXT (e.g. --filter fill_). --json writes the
// rows to FILE as well (one object per case: name, triangles, facet_ms, llvmpipe_ms, ratio,
// mean_diff, within2, psnr, threads, width, height, facet_depth_view_timed, pixel_precision, samples), for
// tools/charts.
// With no scene file: the built-in scene, the Stanford bunny (when ../shared/models is there) and
// a 1M-triangle sphere, each with 1, 4 and 8 lights. --check exits 1 unless every comparison has
// a mean difference <= 0.05 steps, >= 99.9 % of covered pixels within 2 steps and a PSNR >= 50 dB
// (multisampled frames: mean <= 1 step, >= 97 % within 2, at most 0.2 % more than 8 steps away)
// (the test). Measured on the --quick scenes at 480x270: mean 0.001-0.006 steps, 100.00 % within
// 2 steps, 60-78 dB: the bounds leave about 8x on the mean and 10 dB on the PSNR for another
// CPU's llvmpipe, and are 20x tighter than the project's GL-compatibility target (mean <= 1 step,
// >= 99 % within 2), which a wrong attenuation, cone or pow would still have passed.
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "../fill_scenes.hpp"
#include "../repo_scenes.hpp"
#include "facet/facet.hpp"
#include "gl_scene.hpp"

namespace {

using namespace gl_compare;
using Clock = std::chrono::steady_clock;

struct Options {
  int threads = 2, width = 1920, height = 1080;
  double seconds = 1.0;
  std::string out = "out/llvmpipe";
  bool quick = false, check = false;
  bool rounds = false;  // --rounds: print each timed round
  std::string filter;  // run only the cases whose name contains it
  std::string json;    // also write the rows there
  int lights = 0;      // > 0: scene files get this many of the built-in cases' GL 2.1 lights instead of theirs
  bool srgb = false;   // --srgb: both encode their output to sRGB (facet: RenderOptions::srgb; GL: an sRGB FBO)
  bool phong = false;  // --shading phong: facet lights per pixel (GL still per vertex)
  bool with_depth = false;  // --with-depth: facet writes its depth view in the timed rounds too
  facet::PixelPrecision precision = facet::PixelPrecision::automatic;  // --pixel-precision
  int msaa = 1;  // --msaa N: both renderers multisample (facet: RenderOptions::samples; GL: a multisampled FBO)
  std::vector<std::string> scenes;  // scene files or models
  std::vector<std::string> allow_paths;  // --allow-path: folders their files may also come from
};

struct Result {
  std::string name;
  std::size_t triangles = 0;
  double facet_ms = 0, gl_ms = 0;
  double mean_diff = 0, within2 = 0, psnr = 0;
  std::size_t covered = 0;
  std::size_t histogram[6] = {};  // covered pixels by largest channel difference: 0, 1, 2, 3-4, 5-8, > 8
  bool surfaces = false;          // the scene has textures, vertex colours, blending, alpha test or fog
};

// llvmpipe's target when it is not OSMesa's buffer: a framebuffer object with a colour (sRGB with
// --srgb, GL_FRAMEBUFFER_SRGB on) and a depth renderbuffer, multisampled with --msaa N (GL_MULTISAMPLE
// is on by default), bound; a multisampled one is resolved every frame by glBlitFramebuffer into a
// second, single-sample object of the same formats, which is what is read back (GL 3.0's entry
// points, from OSMesa).
struct GlTarget {
  GLuint fbo = 0, colour = 0, depth = 0;                       // drawn into
  GLuint resolved = 0, resolved_colour = 0, resolved_depth = 0;  // --msaa: the blit's target
  bool srgb = false;
  int samples = 1, w = 0, h = 0;
  PFNGLGENFRAMEBUFFERSPROC gen_framebuffers = nullptr;
  PFNGLBINDFRAMEBUFFERPROC bind_framebuffer = nullptr;
  PFNGLGENRENDERBUFFERSPROC gen_renderbuffers = nullptr;
  PFNGLBINDRENDERBUFFERPROC bind_renderbuffer = nullptr;
  PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC storage = nullptr;
  PFNGLFRAMEBUFFERRENDERBUFFERPROC attach = nullptr;
  PFNGLCHECKFRAMEBUFFERSTATUSPROC check = nullptr;
  PFNGLBLITFRAMEBUFFERPROC blit = nullptr;
  PFNGLDELETEFRAMEBUFFERSPROC delete_framebuffers = nullptr;
  PFNGLDELETERENDERBUFFERSPROC delete_renderbuffers = nullptr;
  template <class P>
  static bool get(P& p, const char* name) {
    p = reinterpret_cast<P>(OSMesaGetProcAddress(name));
    return p != nullptr;
  }
  bool make_one(GLuint& f, GLuint& c, GLuint& d, int n) {
    gen_framebuffers(1, &f);
    bind_framebuffer(GL_FRAMEBUFFER, f);
    gen_renderbuffers(1, &c);
    bind_renderbuffer(GL_RENDERBUFFER, c);
    storage(GL_RENDERBUFFER, n > 1 ? n : 0, srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, w, h);
    attach(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, c);
    gen_renderbuffers(1, &d);
    bind_renderbuffer(GL_RENDERBUFFER, d);
    storage(GL_RENDERBUFFER, n > 1 ? n : 0, GL_DEPTH_COMPONENT24, w, h);
    attach(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, d);
    return check(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  }
  bool make(int width, int height, bool use_srgb, int sample_count) {
    w = width, h = height, srgb = use_srgb, samples = sample_count;
    if (!get(gen_framebuffers, "glGenFramebuffers") || !get(bind_framebuffer, "glBindFramebuffer") ||
        !get(gen_renderbuffers, "glGenRenderbuffers") || !get(bind_renderbuffer, "glBindRenderbuffer") ||
        !get(storage, "glRenderbufferStorageMultisample") || !get(attach, "glFramebufferRenderbuffer") ||
        !get(check, "glCheckFramebufferStatus") || !get(blit, "glBlitFramebuffer") ||
        !get(delete_framebuffers, "glDeleteFramebuffers") || !get(delete_renderbuffers, "glDeleteRenderbuffers")) {
      std::fprintf(stderr, "--srgb / --msaa: this GL has no framebuffer objects\n");
      return false;
    }
    if (samples > 1 && !make_one(resolved, resolved_colour, resolved_depth, 1)) {
      std::fprintf(stderr, "--msaa: the resolve framebuffer is not complete\n");
      return false;
    }
    if (!make_one(fbo, colour, depth, samples)) {
      std::fprintf(stderr, "--srgb / --msaa: the framebuffer is not complete\n");
      return false;
    }
    if (srgb) glEnable(GL_FRAMEBUFFER_SRGB);
    return true;
  }
  // After a frame: a multisampled target's samples resolved (colour averaged, depth one sample).
  void resolve() {
    if (samples <= 1) return;
    bind_framebuffer(GL_READ_FRAMEBUFFER, fbo);
    bind_framebuffer(GL_DRAW_FRAMEBUFFER, resolved);
    blit(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    bind_framebuffer(GL_FRAMEBUFFER, fbo);
  }
  // Binds what the frame's pixels are read from.
  void bind_for_reading() { bind_framebuffer(GL_FRAMEBUFFER, samples > 1 ? resolved : fbo); }
  void release() {
    if (srgb) glDisable(GL_FRAMEBUFFER_SRGB);
    bind_framebuffer(GL_FRAMEBUFFER, 0);
    for (GLuint* r : {&colour, &depth, &resolved_colour, &resolved_depth}) {
      if (*r) delete_renderbuffers(1, r);
    }
    for (GLuint* f : {&fbo, &resolved}) {
      if (*f) delete_framebuffers(1, f);
    }
  }
};

template <class Fn>
double ms_per_frame(Fn&& frame, double seconds) {
  frame();  // warm-up (JIT compilation, buffers)
  int n = 0;
  const auto t0 = Clock::now();
  do {
    frame();
    ++n;
  } while (std::chrono::duration<double>(Clock::now() - t0).count() < seconds || n < 3);
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / n;
}

bool compare(const std::string& name, const facet::Scene& scene, const Options& opt, OSMesaContext ctx, Result& r) {
  const int w = opt.width, h = opt.height;
  r.name = name;
  for (const auto& o : scene.objects) r.triangles += scene.meshes[o.mesh].mesh.triangle_count();
  // llvmpipe.
  std::vector<std::uint8_t> gl_pixels(static_cast<std::size_t>(w * h * 4));
  if (!OSMesaMakeCurrent(ctx, gl_pixels.data(), GL_UNSIGNED_BYTE, w, h)) {
    std::fprintf(stderr, "OSMesaMakeCurrent failed\n");
    return false;
  }
  // --srgb: llvmpipe draws into a framebuffer object with an sRGB colour buffer and
  // GL_FRAMEBUFFER_SRGB on (EXT_framebuffer_sRGB: blending in linear, each write encoded), read
  // back after the timed rounds; facet encodes its linear result once when it stores it.
  // --msaa N: llvmpipe draws into a multisampled framebuffer object, resolved by a blit every
  // frame (part of its timed frame); facet renders with RenderOptions::samples = N.
  GlTarget target;
  const bool use_target = opt.srgb || opt.msaa > 1;
  if (use_target && !target.make(w, h, opt.srgb, opt.msaa)) return false;
  GlScene g = gl_prepare(scene, opt.phong);
  // facet, into the same layout (OSMesa's buffer is bottom row first: y_up).
  std::vector<std::uint8_t> facet_pixels(static_cast<std::size_t>(w * h * 4));
  std::vector<float> facet_depth(static_cast<std::size_t>(w * h));
  const facet::ImageView view{facet_pixels.data(), w, h, static_cast<std::size_t>(w) * 4, facet::PixelFormat::rgba8, true};
  const facet::DepthView dview{facet_depth.data(), w, h, static_cast<std::size_t>(w) * sizeof(float), true};
  facet::RenderOptions ro;
  ro.threads = opt.threads;
  ro.srgb = opt.srgb;
  ro.depth = facet::DepthMode::gl;  // GL's window depth, compared with llvmpipe's
  if (opt.phong) ro.shading = facet::ShadingMode::phong;
  ro.pixel_precision = opt.precision;
  ro.samples = opt.msaa;
  facet::Renderer renderer(ro);
  facet::Status status;
  // The two renderers take turns (three rounds when timed), and each reports its median round:
  // this machine's speed drifts over seconds, and one renderer timed wholly before the other
  // would carry the drift into the ratio.
  const int rounds = opt.seconds > 0 ? 3 : 1;
  std::vector<double> gl_rounds, facet_rounds;
  // The same work on both sides: llvmpipe keeps its depth inside GL, so facet is timed without a
  // depth view (its depth stays in its tiles) unless --with-depth asks for the old measurement;
  // the depth images are read after the timed rounds, for the comparison.
  const facet::DepthView* timed_depth = opt.with_depth ? &dview : nullptr;
  for (int k = 0; k < rounds && status.ok(); ++k) {
    gl_rounds.push_back(ms_per_frame(
        [&] {
          gl_draw(scene, g, w, h);
          if (use_target) {
            target.resolve();
            glFinish();
          }
        },
        opt.seconds / rounds));
    facet_rounds.push_back(ms_per_frame([&] { status = renderer.render(scene, view, timed_depth); }, opt.seconds / rounds));
  }
  if (status.ok() && !opt.with_depth) status = renderer.render(scene, view, &dview);  // the compared frame, with its depth
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  if (opt.rounds) {
    std::printf("%s rounds, ms (llvmpipe / facet):", name.c_str());
    for (std::size_t k = 0; k < gl_rounds.size(); ++k) std::printf(" %.2f / %.2f", gl_rounds[k], facet_rounds[k]);
    std::printf("\n");
  }
  r.gl_ms = median(gl_rounds);
  r.facet_ms = median(facet_rounds);
  gl_release(g);
  r.surfaces = has_surfaces(scene);
  std::vector<float> gl_depth(static_cast<std::size_t>(w * h));
  if (use_target) target.bind_for_reading();
  glReadPixels(0, 0, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, gl_depth.data());
  if (use_target) {
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, gl_pixels.data());
    target.release();
  }
  if (!status.ok()) {
    std::fprintf(stderr, "facet: %s\n", status.message().c_str());
    return false;
  }
  // Differences over the pixels either covered.
  double sum = 0, sq = 0;
  std::size_t within = 0, channels = 0;
  for (std::size_t i = 0; i < gl_depth.size(); ++i) {
    // Covered: either renderer wrote depth there, or changed the colour from the clear colour
    // (blended geometry does not write depth).
    const bool drawn = gl_pixels[4 * i] | gl_pixels[4 * i + 1] | gl_pixels[4 * i + 2] | facet_pixels[4 * i] |
                       facet_pixels[4 * i + 1] | facet_pixels[4 * i + 2];
    if (!(gl_depth[i] < 1.0f || facet_depth[i] < 1.0f || drawn)) continue;
    ++r.covered;
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int d = std::abs(int(gl_pixels[4 * i + c]) - int(facet_pixels[4 * i + c]));
      sum += d, sq += double(d) * d, ++channels;
      worst = std::max(worst, d);
    }
    within += worst <= 2;
    ++r.histogram[worst == 0 ? 0 : worst == 1 ? 1 : worst == 2 ? 2 : worst <= 4 ? 3 : worst <= 8 ? 4 : 5];
  }
  r.mean_diff = channels ? sum / double(channels) : 0;
  r.within2 = r.covered ? double(within) / double(r.covered) : 1;
  r.psnr = sq > 0 ? 10 * std::log10(255.0 * 255.0 * double(channels) / sq) : INFINITY;
  // Both images, top row first.
  std::filesystem::create_directories(opt.out);
  const std::string stem = opt.out + "/" + name;
  const facet::ImageView gl_view{gl_pixels.data(), w, h, static_cast<std::size_t>(w) * 4, facet::PixelFormat::rgba8, true};
  (void)facet::write_png(stem + "_llvmpipe.png", gl_view);
  (void)facet::write_png(stem + "_facet.png", view);
  return true;
}

facet::Scene sphere_scene(int triangles) {
  facet::Scene s;
  const int rings = static_cast<int>(std::sqrt(triangles / 4.0));
  s.meshes.push_back({"sphere", facet::make_uv_sphere(1.0f, 2 * rings, rings)});
  facet::Material m;
  m.diffuse = facet::Color3(0.7f, 0.6f, 0.5f);
  m.specular = facet::Color3(0.5f, 0.5f, 0.5f);
  m.shininess = 32;
  s.materials.push_back(m);
  s.objects.push_back({0, 0, facet::Mat4::Identity()});
  s.camera.eye = facet::Vec3(0, 0.5f, 3.2f);
  return s;
}

}  // namespace

// A scene file or a model, as `facet render` reads it: a model without a camera is framed for the
// image's aspect, one without lights gets facet's default rig. Files may come from the file's own
// folder, the repository's data folders and the --allow-path folders.
facet::Result<facet::Scene> load_any(const std::string& path, const Options& opt) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  facet::LoadOptions lo = repo_scene_options();
  for (const std::string& a : opt.allow_paths) lo.assets.allowed_roots.push_back(a);
  lo.frame_aspect = float(opt.width) / float(opt.height);
  // GL has neither exposure nor tone mapping: the comparison draws every scene with GL's display.
  lo.gl_materials = true;
  if (ext != ".gltf" && ext != ".glb" && ext != ".obj") {
    facet::Result<facet::Scene> s = facet::load_scene_file(path, lo);
    if (s) s->display = facet::Display{};
    return s;
  }
  facet::ModelOptions mo;
  mo.assets = lo.assets;
  mo.gl_materials = true;  // GL's lighting model: what llvmpipe draws
  facet::Result<facet::Model> m = facet::load_model(path, mo);
  if (!m) return m.status();
  if (!m->has_camera) {
    facet::Result<facet::Camera> c = facet::frame_scene(m->scene, lo.frame_aspect);
    if (!c) return c.status();
    m->scene.camera = *c;
  }
  if (!m->has_lights) facet::add_default_lights(m->scene);
  m->scene.display = facet::Display{};
  return std::move(m->scene);
}

int main(int argc, char** argv) {
  Options opt;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "facet_vs_llvmpipe: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--threads") opt.threads = std::atoi(next());
    else if (a == "--width") opt.width = std::atoi(next());
    else if (a == "--height") opt.height = std::atoi(next());
    else if (a == "--seconds") opt.seconds = std::atof(next());
    else if (a == "--out") opt.out = next();
    else if (a == "--quick") opt.quick = true;
    else if (a == "--check") opt.check = true;
    else if (a == "--rounds") opt.rounds = true;
    else if (a == "--filter") opt.filter = next();
    else if (a == "--allow-path") opt.allow_paths.push_back(next());
    else if (a == "--json") opt.json = next();
    else if (a == "--lights") opt.lights = std::atoi(next());
    else if (a == "--srgb") opt.srgb = true;
    else if (a == "--with-depth") opt.with_depth = true;
    else if (a == "--msaa") {
      opt.msaa = std::atoi(next());
      if (opt.msaa != 1 && opt.msaa != 4 && opt.msaa != 8 && opt.msaa != 16) {
        std::fprintf(stderr, "facet_vs_llvmpipe: --msaa 1|4|8|16\n");
        return 2;
      }
    }
    else if (a == "--pixel-precision") {
      const std::string v = next();
      if (v != "auto" && v != "exact" && v != "fast") {
        std::fprintf(stderr, "facet_vs_llvmpipe: --pixel-precision auto|exact|fast\n");
        return 2;
      }
      opt.precision = v == "exact" ? facet::PixelPrecision::exact
                      : v == "fast" ? facet::PixelPrecision::fast
                                    : facet::PixelPrecision::automatic;
    }
    else if (a == "--shading") {
      const std::string v = next();
      if (v != "gouraud" && v != "phong") {
        std::fprintf(stderr, "facet_vs_llvmpipe: --shading gouraud|phong\n");
        return 2;
      }
      opt.phong = v == "phong";
    }
    else if (a == "-h" || a == "--help") {
      std::puts("usage: facet_vs_llvmpipe [--threads N] [--width W] [--height H] [--seconds S] [--out DIR] [--quick] [--check] [--rounds] [--filter TEXT] [--json FILE] [--lights N] [--srgb] [--shading gouraud|phong] [--with-depth] [--pixel-precision auto|exact|fast] [--msaa 1|4|8|16] [--allow-path DIR] [SCENE.json | MODEL.gltf | MODEL.glb | MODEL.obj ...]");
      return 0;
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "facet_vs_llvmpipe: unknown option %s\n", a.c_str());
      return 2;
    } else {
      opt.scenes.push_back(a);
    }
  }
  if (opt.threads < 1 || opt.threads > 64 || opt.width < 1 || opt.height < 1 || opt.width > 8192 || opt.height > 8192 ||
      opt.lights < 0 || opt.lights > 8) {
    std::fprintf(stderr, "facet_vs_llvmpipe: --threads 1..64, sizes 1..8192, --lights 0..8\n");
    return 2;
  }
  // llvmpipe reads its thread count when the first context is created (this program's own
  // environment; the facet library reads none).
  setenv("LP_NUM_THREADS", std::to_string(opt.threads).c_str(), 1);
  OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!ctx) {
    std::fprintf(stderr, "OSMesaCreateContextExt failed\n");
    return 2;
  }

  std::vector<std::pair<std::string, facet::Scene>> cases;
  if (opt.scenes.empty()) {
    std::vector<std::pair<std::string, facet::Scene>> bases;
    bases.emplace_back("default", facet::make_default_scene());
    const auto bunny = facet::load_scene_file(std::string(FACET_SOURCE_DIR) + "/tests/data/scenes/bunny.json", repo_scene_options());
    if (bunny) {
      bases.emplace_back("bunny", *bunny);
    } else {
      std::fprintf(stderr, "skipping the bunny: %s\n", bunny.status().message().c_str());
    }
    bases.emplace_back(opt.quick ? "sphere64k" : "sphere1m", sphere_scene(opt.quick ? 65536 : 1 << 20));
    for (auto& [name, base] : bases) {
      // GL 2.1 caps shininess at 128 (the built-in scene has a 200): both renderers get 128.
      for (auto& m : base.materials) m.shininess = std::min(m.shininess, 128.0f);
      // These are the lighting comparisons, held to the tight bounds: opaque and untextured (the
      // surfaces cases below check textures and blending).
      for (auto& m : base.materials) {
        m.diffuse_texture = facet::kNoTexture;
        m.blend = facet::BlendMode::opaque;
        m.alpha = 1.0f;
      }
      base.textures.clear();
      facet::Vec3 c;
      float radius;
      bounds(base, c, radius);
      for (int lights : opt.quick ? std::vector<int>{4} : std::vector<int>{1, 4, 8}) {
        facet::Scene s = base;
        s.lights = light_set(lights, c, radius);
        cases.emplace_back(name + "_" + std::to_string(lights) + "lights", std::move(s));
      }
    }
    // Surfaces: the done-when scene of issue 15 (textures, separate specular, blending, fog), and
    // the built-in scene with vertex colours and an alpha-tested, decal-textured ground.
    const std::string surfaces_file = std::string(FACET_SOURCE_DIR) + "/tests/data/scenes/surfaces.json";
    if (!std::filesystem::exists(surfaces_file)) {
      // An installed program away from its source tree: the surfaces cases need the repository's files.
      std::fprintf(stderr, "skipping the surfaces cases: %s is not there (give scene or model files instead)\n", surfaces_file.c_str());
    }
    const auto surfaces = facet::load_scene_file(surfaces_file, repo_scene_options());
    if (!surfaces && std::filesystem::exists(surfaces_file)) {
      std::fprintf(stderr, "%s\n", surfaces.status().message().c_str());
      return 2;
    }
    if (surfaces) {  // the repository's scene files are there
      cases.emplace_back("surfaces", *surfaces);
      // Alpha to coverage (--msaa): foliage cards with soft-edged leaves and a ball in screen-door
      // transparency.
      const auto coverage = facet::load_scene_file(std::string(FACET_SOURCE_DIR) + "/tests/data/scenes/coverage.json", repo_scene_options());
      if (!coverage) {
        std::fprintf(stderr, "%s\n", coverage.status().message().c_str());
        return 2;
      }
      cases.emplace_back("alpha_to_coverage", *coverage);
      // Emission after the texture: a glowing grid on the ground (an emissive texture over its
      // checker), the painted ball's emission after its stripes, and an emissive texture alone on
      // the box.
      {
        facet::Scene glow = *surfaces;
        std::vector<std::uint8_t> grid(32 * 32 * 4);
        for (int j = 0; j < 32; ++j)
          for (int i = 0; i < 32; ++i) {
            const bool line = i % 8 < 2 || j % 8 < 2;
            std::uint8_t* p = grid.data() + 4 * (j * 32 + i);
            p[0] = line ? 255 : 20, p[1] = line ? 200 : 10, p[2] = line ? 60 : 30, p[3] = 255;
          }
        facet::TextureOptions to;
        to.filter = facet::TextureFilter::trilinear;
        auto t = facet::make_texture("grid", 32, 32, grid, to);
        if (!t) {
          std::fprintf(stderr, "%s\n", t.status().message().c_str());
          return 2;
        }
        glow.textures.push_back(std::move(*t));
        const auto grid_index = static_cast<std::int32_t>(glow.textures.size() - 1);
        for (auto& m : glow.materials) {
          if (m.name == "ground") {
            m.emissive = facet::Color3(0.7f, 0.6f, 0.5f);
            m.emissive_texture = grid_index;
          } else if (m.name == "painted") {
            m.emissive = facet::Color3(0.25f, 0.1f, 0.05f);
            m.emission_after_texture = true;
          } else if (m.name == "red") {
            m.emissive = facet::Color3(1.0f, 1.0f, 1.0f);
            m.emissive_texture = grid_index;
          }
        }
        cases.emplace_back("emissive_textures", std::move(glow));
      }
      // Back-to-front order: three overlapping blended balls in two colours, submitted near to far
      // and before the opaque objects; facet sorts them, GL draws them in facet's order.
      {
        facet::Scene sorted = *surfaces;
        sorted.transparent_order = facet::TransparentOrder::back_to_front;
        facet::Material amber = sorted.materials[sorted.objects.back().material];  // the glass
        amber.name = "amber";
        amber.ambient = amber.diffuse = facet::Color3(1.0f, 0.6f, 0.1f);
        amber.alpha = 0.6f;
        sorted.materials.push_back(amber);
        facet::Instance near_ball = sorted.objects.back(), middle = near_ball, far_ball = near_ball;
        middle.material = static_cast<std::uint32_t>(sorted.materials.size() - 1);
        middle.model(0, 3) = 0.5f, middle.model(2, 3) = 0.0f;
        far_ball.model(0, 3) = -0.2f, far_ball.model(1, 3) = 1.3f, far_ball.model(2, 3) = -1.4f;
        std::vector<facet::Instance> objects = {near_ball, middle, far_ball};
        objects.insert(objects.end(), sorted.objects.begin(), sorted.objects.end() - 1);
        sorted.objects = std::move(objects);
        cases.emplace_back("transparent_order", std::move(sorted));
      }
    }
    facet::Scene coloured = facet::make_default_scene();
    for (auto& m : coloured.materials) m.shininess = std::min(m.shininess, 128.0f);
    for (auto& nm : coloured.meshes) {
      nm.mesh.colors.resize(nm.mesh.vertex_count());
      for (std::size_t v = 0; v < nm.mesh.colors.size(); ++v) {
        const facet::Vec3& p = nm.mesh.positions[v];
        nm.mesh.colors[v] = facet::Color3(0.5f + 0.5f * std::sin(3 * p.x()), 0.5f + 0.5f * std::cos(2 * p.y()),
                                          0.5f + 0.5f * std::sin(p.z() + 1));
      }
    }
    facet::Vec3 centre;
    float radius;
    bounds(coloured, centre, radius);
    coloured.lights = light_set(4, centre, radius);  // the built-in lights have ranges (not GL 2.1)
    cases.emplace_back("vertex_colours", std::move(coloured));
    // Fill rate with surfaces: the frame benchmarks' 16 full-screen layers (bench/fill_scenes.hpp).
    cases.emplace_back("fill_gouraud", facet::bench::layers_scene(16));
    cases.emplace_back("fill_textured", facet::bench::layers_scene(16, false, facet::bench::Layers::textured));
    cases.emplace_back("fill_textured_fog", facet::bench::layers_scene(16, false, facet::bench::Layers::textured_fog));
    cases.emplace_back("fill_blended", facet::bench::layers_scene(16, false, facet::bench::Layers::blended));
  } else {
    for (const std::string& path : opt.scenes) {
      auto s = load_any(path, opt);
      if (!s) {
        std::fprintf(stderr, "%s\n", s.status().message().c_str());
        return 2;
      }
      if (opt.lights > 0) {  // GL 2.1-expressible lights and shininess, as the built-in cases
        facet::Vec3 c;
        float radius;
        bounds(*s, c, radius);
        s->lights = light_set(opt.lights, c, radius);
        for (auto& m : s->materials) m.shininess = std::min(m.shininess, 128.0f);
      }
      cases.emplace_back(std::filesystem::path(path).stem().string(), *s);
    }
  }

  std::printf("facet vs llvmpipe (OSMesa), %dx%d, %d thread%s each, %s, depth test, back faces culled\n\n",
              opt.width, opt.height, opt.threads, opt.threads == 1 ? "" : "s",
              opt.phong ? "facet Phong (per pixel), GL Gouraud" : "Gouraud");
  std::printf("%-22s %10s %12s %12s %8s %10s %10s %9s   %s\n", "scene", "triangles", "facet ms", "llvmpipe ms", "ratio",
              "mean diff", "within 2", "PSNR dB", "pixels by largest difference: 0 / 1 / 2 / 3-4 / 5-8 / >8 steps");
  bool ok = true;
  std::string json = "[";
  for (auto& [name, scene] : cases) {
    if (!opt.filter.empty() && name.find(opt.filter) == std::string::npos) continue;
    if (const std::string why = gl_incompatibility(scene, opt.phong); !why.empty()) {
      std::printf("%-22s skipped: %s\n", name.c_str(), why.c_str());
      continue;
    }
    Result r;
    if (!compare(name, scene, opt, ctx, r)) return 2;
    std::printf("%-22s %10zu %12.2f %12.2f %7.2fx %10.3f %9.2f%% %9.1f  ", r.name.c_str(), r.triangles, r.facet_ms,
                r.gl_ms, r.gl_ms / r.facet_ms, r.mean_diff, 100 * r.within2, r.psnr);
    for (std::size_t k = 0; k < 6; ++k) {
      std::printf(" %.2f%%", r.covered ? 100.0 * double(r.histogram[k]) / double(r.covered) : 0.0);
    }
    std::printf("\n");
    char row[512];
    std::snprintf(row, sizeof row,
                  "%s\n  {\"name\": \"%s\", \"triangles\": %zu, \"facet_ms\": %.4f, \"llvmpipe_ms\": %.4f, "
                  "\"ratio\": %.4f, \"mean_diff\": %.4f, \"within2\": %.6f, \"psnr\": %.2f, \"threads\": %d, "
                  "\"width\": %d, \"height\": %d, \"facet_depth_view_timed\": %s, \"pixel_precision\": \"%s\", \"samples\": %d}",
                  json.size() > 1 ? "," : "", r.name.c_str(), r.triangles, r.facet_ms, r.gl_ms, r.gl_ms / r.facet_ms,
                  r.mean_diff, r.within2, std::isfinite(r.psnr) ? r.psnr : 999.0, opt.threads, opt.width, opt.height,
                  opt.with_depth ? "true" : "false", facet::to_string(opt.precision), opt.msaa);
    json += row;
    // Surfaces and multisampled frames: the GL-compatibility target (llvmpipe averages 8-bit
    // samples, facet float ones, so edges round apart by a step).
    if (r.surfaces || opt.msaa > 1) {
      if (r.mean_diff > 1.0 || r.within2 < 0.97) ok = false;
      // Multisampled: the worst pixels too. Measured 2026-11-28 on the quick scenes at 480x270,
      // 4 samples: at most 0.05 % of covered pixels more than 8 steps from GL; a sample pattern
      // mirrored in y puts 0.33-1.25 % there.
      const double beyond8 = r.covered ? double(r.histogram[5]) / double(r.covered) : 0.0;
      if (opt.msaa > 1 && beyond8 > 0.002) {
        std::fprintf(stderr, "facet_vs_llvmpipe: %s: %.2f %% of covered pixels more than 8 steps from GL (at most 0.2 %%)\n",
                     r.name.c_str(), 100 * beyond8);
        ok = false;
      }
    } else if (r.mean_diff > 0.05 || r.within2 < 0.999 || r.psnr < 50.0) {
      ok = false;
    }
  }
  const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  std::printf("\nGL: %s, %s; ratio = llvmpipe ms / facet ms; images in %s/\n", renderer ? renderer : "?",
              version ? version : "?", opt.out.c_str());
  OSMesaDestroyContext(ctx);
  if (!opt.json.empty()) {
    std::FILE* f = std::fopen(opt.json.c_str(), "w");
    if (!f || std::fprintf(f, "%s\n]\n", json.c_str()) < 0 || std::fclose(f) != 0) {
      std::fprintf(stderr, "facet_vs_llvmpipe: cannot write %s\n", opt.json.c_str());
      return 2;
    }
  }
  if (opt.check && !ok) {
    std::fprintf(stderr, "facet_vs_llvmpipe: a lighting comparison exceeds a mean of 0.05 steps, has < 99.9%% within 2 "
                         "steps or a PSNR below 50 dB, or a surfaces comparison a mean of 1 step or < 97%% within 2\n");
    return 1;
  }
  return 0;
}
