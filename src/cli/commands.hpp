// The subcommands of `pfill`; each file src/cli/*_command.cpp adds one.
#pragma once
#include <CLI/CLI.hpp>

namespace pfill {

/// `pfill render PARTICLES|FRAMES_DIR -o OUT [--mesh SHAPE] [--view V] [--size WxH] [--cut x|y|z[=v]]`
void add_render_command(CLI::App& app);

}  // namespace pfill
