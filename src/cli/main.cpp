// pfill's command line: subcommands are added by src/cli/*_command.cpp;
// every pfill::Error becomes one line on stderr and exit status 1.
#include <cstdio>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "pfill/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"pfill: fill closed triangle meshes with densely packed spherical particles"};
  app.require_subcommand(1);
  pfill::add_render_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const pfill::Error& e) {
    std::fprintf(stderr, "pfill: %s\n", e.what());
    return 1;
  }
  return 0;
}
