// The subcommands of `pfill`, each added to the CLI11 app by one function.
#pragma once
#include <CLI/CLI.hpp>

void add_devices_command(CLI::App& app);
