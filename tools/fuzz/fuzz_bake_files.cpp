// Fuzzes the files facet bake carries into its folder (tools/facet/baked_scene.cpp): any scene
// file, in a folder that holds a model, a texture, and links that lead out to a canary, is loaded
// as facet bake loads it (the files read recorded), and its baked scene written into a fresh
// folder. Whatever the scene names, no byte of the canary is copied, nothing is written outside
// the output folder (the canary's folder keeps exactly its one file), and no link is made.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "facet/baked_scene.hpp"
#include "fuzz_support.hpp"

namespace {

namespace fs = std::filesystem;
constexpr const char* kCanary = "CANARY-0123456789";

// base/outside/canary.png, base/scene/{m.obj, sub/m.mtl, sub/t.png, link.png -> ../outside/canary.png,
// out -> ../outside}; made once per process.
const fs::path& base() {
  static const fs::path root = [] {
    const fs::path b = fs::temp_directory_path() / ("facet_fuzz_bake_files_" + std::to_string(::getpid()));
    fs::remove_all(b);
    fs::create_directories(b / "outside");
    fs::create_directories(b / "scene" / "sub");
    std::ofstream(b / "outside" / "canary.png") << kCanary;
    std::ofstream(b / "scene" / "m.obj") << "mtllib sub/m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl m\nf 1/1 2/1 3/1\n";
    std::ofstream(b / "scene" / "sub" / "m.mtl") << "newmtl m\nKd 1 1 1\nmap_Kd t.tga\nmap_Ks ../link.png\n";
    // A 1 x 1 true-colour TGA.
    std::ofstream(b / "scene" / "sub" / "t.tga", std::ios::binary) << std::string("\0\0\2\0\0\0\0\0\0\0\0\0\1\0\1\0\x18\0\x10\x20\x30", 21);
    std::error_code ec;
    fs::create_symlink("../outside/canary.png", b / "scene" / "link.png", ec);
    fs::create_symlink("../outside", b / "scene" / "out", ec);
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(fs::temp_directory_path() / ("facet_fuzz_bake_files_" + std::to_string(::getpid())), ignored);
    });
    return b;
  }();
  return root;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace facet;
  const fs::path& b = base();
  const std::string scene_path = (b / "scene" / "scene.json").string();
  {
    std::ofstream f(scene_path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  cli::Files read;
  LoadOptions lo;
  lo.memory_budget_bytes = 64u << 20;
  lo.assets.on_read = [&read](const std::string& name, const std::string& bytes) { read.emplace(cli::loader_name(name), bytes); };
  Result<Scene> scene = load_scene_file(scene_path, lo);
  if (!scene || scene->objects.size() > 64) return 0;
  // A bake's result in shape only: one lightmap an object (no light is computed).
  BakeResult r;
  r.lightmaps.resize(scene->objects.size());
  for (std::size_t k = 0; k < r.lightmaps.size(); ++k) r.lightmaps[k].object = static_cast<std::uint32_t>(k);
  const fs::path out = b / "baked";
  fs::remove_all(out);
  Result<cli::OutputFolder> folder = cli::OutputFolder::open(out.string(), false);
  if (!folder) fuzz::broken("a fresh output folder is refused");
  std::string note;
  (void)cli::write_baked_scene({scene_path, "diffuse", {}}, *folder, read, BakeOptions{}, 1.0, r, note);
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (e.is_symlink()) fuzz::broken("a link in the baked folder");
    if (!e.is_regular_file()) continue;
    std::ifstream in(e.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.find(kCanary) != std::string::npos) fuzz::broken("the canary outside the scene's folder was copied");
  }
  const auto outside = std::distance(fs::recursive_directory_iterator(b / "outside"), fs::recursive_directory_iterator());
  if (outside != 1) fuzz::broken("a file was written outside the output folder");
  return 0;
}
