// pfill: fill a closed triangle mesh with densely packed spherical particles.
// `pfill` alone fills a built-in shape (the same as `pfill fill`).
// Exit codes (cli/commands.hpp, README): 0 success, 1 error (one line on
// stderr), 2 bad usage, 3 `check` missed a threshold.
#include <iostream>
#include <string>
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
  app.footer("Exit codes: 0 success, 1 error (one line on stderr), 2 bad usage, 3 `check` missed a threshold.");
  // `--help-all`: the help with every option, the tuning ones included.
  std::vector<const char*> args(argv, argv + argc);
  bool show_all = false;
  for (const char*& a : args)
    if (std::string(a) == "--help-all") {
      show_all = true;
      a = "--help";
    }
  pfill::cli::add_fill_command(app, show_all);
  pfill::cli::add_check_command(app);
  pfill::cli::add_info_command(app);
  pfill::cli::add_render_command(app);
  pfill::cli::add_devices_command(app);
  pfill::cli::add_contacts_command(app);
  pfill::cli::add_surface_command(app);
  pfill::cli::add_join_command(app);

  if (argc == 1) args.push_back("fill");  // the main job on a built-in shape
  // CLI11 answers a mistyped command with "A subcommand is required": name it.
  if (argc > 1 && argv[1][0] != '-') {
    std::string known;
    bool found = false;
    for (const CLI::App* sub : app.get_subcommands({})) {
      found = found || sub->get_name() == argv[1];
      known += (known.empty() ? "" : ", ") + sub->get_name();
    }
    if (!found) {
      std::cerr << "pfill: error: unknown command '" << argv[1] << "': use one of " << known
                << " (e.g. pfill fill MESH -o out.ply; pfill --help)\n";
      return pfill::cli::kExitUsage;
    }
  }
  try {
    app.parse(static_cast<int>(args.size()), const_cast<char**>(args.data()));
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e) == 0 ? pfill::cli::kExitOk : pfill::cli::kExitUsage;  // --help, --version
    // One line, capped as pfill's own errors are (a 120 KB argument is not echoed whole).
    std::cerr << "pfill: error: " << pfill::excerpt(e.what(), 600) << " (see pfill --help)\n";
    return pfill::cli::kExitUsage;
  } catch (const pfill::cli::ExitStatus& e) {
    return e.status;
  } catch (const std::exception& e) {
    std::cerr << "pfill: error: " << e.what() << "\n";
    return pfill::cli::kExitError;
  }
  return pfill::cli::kExitOk;
}
