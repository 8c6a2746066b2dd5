// Fuzzes the confinement of the files a model names (io/assets.hpp): any name, written by a file in
// a model's folder, is refused or leads into that folder. Through a host's resolver, every name it
// is asked for lies in the folder, normalised (no "." or ".." segment); on disk, every path
// resolved lies in the folder, links followed (the folder holds a link that leads out). Messages
// hold no control character.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_support.hpp"
#include "io/assets.hpp"

namespace {

namespace fs = std::filesystem;

// lib/model/a.bin, lib/secret.bin, lib/model/out -> ../secret.bin (made once per process).
const fs::path& disk_root() {
  static const fs::path root = [] {
    const fs::path base = fs::temp_directory_path() / ("facet_fuzz_assets_" + std::to_string(::getpid()));
    fs::create_directories(base / "model");
    std::ofstream(base / "model" / "a.bin") << "a";
    std::ofstream(base / "secret.bin") << "secret";
    std::error_code ec;
    fs::create_symlink("../secret.bin", base / "model" / "out", ec);
    return base / "model";
  }();
  return root;
}

bool normalised_inside(const std::string& path, const std::string& folder) {
  if (path.rfind(folder + "/", 0) != 0) return false;
  std::size_t at = folder.size() + 1;
  while (at <= path.size()) {
    const std::size_t end = std::min(path.find('/', at), path.size());
    const std::string segment = path.substr(at, end - at);
    if (segment.empty() || segment == "." || segment == "..") return false;
    at = end + 1;
  }
  return true;
}

void check_message(const facet::Status& s) {
  if (s.ok()) return;
  if (s.message().empty()) facet::fuzz::broken("a refusal without a message");
  for (const char c : s.message())
    if (static_cast<unsigned char>(c) < 0x20) facet::fuzz::broken("a control character in a message");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace facet;
  const std::string name(reinterpret_cast<const char*>(data), size);
  {
    AssetAccess access;
    access.resolver = [](const std::string& asked) -> Result<std::string> {
      if (!normalised_inside(asked, "lib/model")) fuzz::broken("the resolver was asked for a name outside the model's folder");
      return std::string("bytes");
    };
    const io::AssetFolder folder(access, "lib/model");
    check_message(folder.read(name, "fuzz.gltf: uri", "file").status());
  }
  {
    const AssetAccess access;
    const std::string root = disk_root().string();
    const io::AssetFolder folder(access, root);
    const Result<io::AssetFolder::Resolved> r = folder.resolve(name, "fuzz.gltf: uri");
    check_message(r.status());
    if (r.ok()) {
      std::error_code ec;
      const fs::path real = fs::weakly_canonical(r->path, ec);
      const std::string real_root = fs::canonical(root).string();
      if (!ec && real.string() != real_root && !normalised_inside(real.string(), real_root)) {
        fuzz::broken("a name resolved to a path outside the model's folder");
      }
    }
  }
  return 0;
}
