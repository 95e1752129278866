// The subcommands of the `pfill` program; each src/cli/*_command.cpp adds one
// to the CLI11 app.
#pragma once
#include <CLI/CLI.hpp>

namespace pfill::cli {

/// Exit statuses of the `pfill` program (listed in the README).
constexpr int kExitOk = 0;
constexpr int kExitError = 1;             ///< one line on stderr: what went wrong and the way out
constexpr int kExitUsage = 2;             ///< bad command line (CLI11's message)
constexpr int kExitThresholdMissed = 3;   ///< `check`: the file was measured and missed a threshold

/// Thrown by a subcommand to end the program with `status` after it has
/// said why (main() prints nothing more).
struct ExitStatus {
  int status;
};

/// `pfill fill [MESH] -o OUT [options]`: the main job; returns the subcommand
/// `show_all`: list the tuning options in --help too (`pfill fill --help-all`).
CLI::App* add_fill_command(CLI::App& app, bool show_all = false);
/// `pfill check PARTICLES MESH [--json]`
void add_check_command(CLI::App& app);
/// `pfill info MESH|--builtin NAME [--json]`
void add_info_command(CLI::App& app);
/// `pfill devices [--device SPEC]`
void add_devices_command(CLI::App& app);
/// `pfill render PARTICLES|FRAMES_DIR -o OUT [--mesh MESH] [--view V] [--size WxH] [--cut x|y|z[=v]]`
void add_render_command(CLI::App& app);

/// `pfill contacts PARTICLES [MESH] [--gap G] -o OUT [--pairs PAIRS.csv]`
void add_contacts_command(CLI::App& app);

/// `pfill surface MESH (-r R | -n N) -o shell.ply`
void add_surface_command(CLI::App& app);

/// `pfill join -o OUT PART...`: the parts a fill wrote per MPI rank, joined by id
void add_join_command(CLI::App& app);

}  // namespace pfill::cli
