// facet — command-line front end: render, check, compare, light, accuracy, bake. Options are parsed by
// CLI11 (`--opt value`, `--opt=value`, `-o`); errors go to stderr with exit status 2 (1 from
// `compare` means "images differ"), and every message names what was wrong.
#include <csignal>
#include <cstdio>
#include <string>

#include "cli.hpp"

namespace {

std::string version_text() {
  std::string isas;
  for (facet::Isa isa : {facet::Isa::sse2, facet::Isa::avx2, facet::Isa::avx512})
    if (facet::isa_supported(isa)) isas += std::string(isas.empty() ? "" : " ") + facet::to_string(isa);
  return std::string("facet ") + facet::version() + " (headers " FACET_VERSION_STRING "); instruction sets on this CPU: " + isas;
}

}  // namespace

int main(int argc, char** argv) {
  // A write past `ulimit -f` then fails with EFBIG and is reported (the old output file is kept)
  // instead of killing the process with SIGXFSZ. The program's choice; the library sets no signal.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app("facet: a CPU renderer. Run 'facet COMMAND --help' for a command's options.", "facet");
  app.set_version_flag("--version", version_text());
  app.require_subcommand(1);
  app.fallthrough(false);
  const facet::cli::Command commands[] = {facet::cli::add_render(app), facet::cli::add_check(app),
                                          facet::cli::add_compare(app), facet::cli::add_light(app),
                                          facet::cli::add_accuracy(app), facet::cli::add_bake(app),
                                          facet::cli::add_compare_runs(app)};
  if (argc < 2) {
    std::fputs(app.help().c_str(), stderr);
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);  // help on stdout, status 0
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string where = "facet --help";
    for (const facet::cli::Command& c : commands)
      if (c.app->parsed()) where = "facet " + c.app->get_name() + " --help";
    return facet::cli::fail(std::string(e.what()) + " (see '" + where + "')");
  }
  for (const facet::cli::Command& c : commands)
    if (c.app->parsed()) return c.run();
  return facet::cli::fail("no command given (see 'facet --help')");
}
