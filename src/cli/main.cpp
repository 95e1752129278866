// pfill: fill a closed triangle mesh with densely packed spherical particles.
// Exit codes: 0 success, 1 error (one line on stderr), 2 bad usage.
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli/commands.hpp"
#include "pfill/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"pfill: fill a closed triangle mesh with densely packed spherical particles"};
  app.set_version_flag("--version", "pfill 0.1.0");
  app.require_subcommand(1);
  pfill::cli::add_info_command(app);
  pfill::cli::add_render_command(app);
  pfill::cli::add_devices_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "pfill: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
