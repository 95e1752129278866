// pfill: fill a closed triangle mesh with densely packed spherical particles.
// `pfill` alone fills a built-in shape (the same as `pfill fill`).
// Exit codes: 0 success, 1 error (one line on stderr), 2 bad usage.
#include <iostream>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/commands.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/error.hpp"

int main(int argc, char** argv) {
  pfill::remove_temporary_files_on_signals();  // Ctrl-C while writing leaves no hidden file
  CLI::App app{"pfill: fill a closed triangle mesh with densely packed spherical particles.\n"
               "Run `pfill` alone to fill a built-in torus, or `pfill fill MESH -o out.ply`."};
  app.set_version_flag("--version", "pfill 0.1.0");
  app.require_subcommand(1);
  pfill::cli::add_fill_command(app);
  pfill::cli::add_check_command(app);
  pfill::cli::add_info_command(app);
  pfill::cli::add_render_command(app);
  pfill::cli::add_devices_command(app);

  std::vector<const char*> args(argv, argv + argc);
  if (argc == 1) args.push_back("fill");  // the main job on a built-in shape
  try {
    app.parse(static_cast<int>(args.size()), const_cast<char**>(args.data()));
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help and --version exit 0
  } catch (const std::exception& e) {
    std::cerr << "pfill: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
