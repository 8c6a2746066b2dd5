// facet — command-line front end: render, compare, light, check, accuracy.
// Errors go to stderr with exit status 2 (1 from `compare` means "images differ"); every message
// names what was wrong.
#include <csignal>
#include <cstdio>
#include <string>

#include "cli.hpp"

namespace {

constexpr const char* kUsage =
    "usage: facet <command> [options]\n"
    "\n"
    "commands:\n"
    "  render [SCENE.json]  render a scene (the built-in default scene if none is given) to PNG or PFM\n"
    "  compare A B          compare two images: PSNR, largest and mean difference, differing pixels\n"
    "  light [SCENE.json]   light every vertex of a scene with each lighting path; print vertices lit per second\n"
    "  check SCENE.json     load and validate a scene file; print a summary or the first error\n"
    "  accuracy             every lighting path, ISA and pow tier against the exact reference\n"
    "\n"
    "run 'facet <command> --help' for the options of a command\n";

}  // namespace

int main(int argc, char** argv) {
  // A write past `ulimit -f` then fails with EFBIG and is reported (the old output file is kept)
  // instead of killing the process with SIGXFSZ. The program's choice; the library sets no signal.
  std::signal(SIGXFSZ, SIG_IGN);
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  const std::string command = argv[1];
  if (command == "-h" || command == "--help" || command == "help") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (command == "render") return facet::cli::run_render(argc - 2, argv + 2);
  if (command == "compare") return facet::cli::run_compare(argc - 2, argv + 2);
  if (command == "light") return facet::cli::run_light(argc - 2, argv + 2);
  if (command == "check") return facet::cli::run_check(argc - 2, argv + 2);
  if (command == "accuracy") return facet::cli::run_accuracy(argc - 2, argv + 2);
  return facet::cli::fail("unknown command '" + command + "'\n" + kUsage);
}
