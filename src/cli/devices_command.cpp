// `pfill devices`: lists the OpenCL devices and marks the one a run would use.
#include <iostream>

#include "cli/commands.hpp"
#include "pfill/device/device.hpp"
#include "pfill/error.hpp"

namespace pfill::cli {

void add_devices_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("devices", "List OpenCL devices (choose one with --device or PFILL_DEVICE)");
  auto spec = std::make_shared<std::string>();
  cmd->add_option("--device", *spec, "Index or name substring of the device to mark as chosen");
  cmd->callback([spec]() {
    const auto devices = pfill::list_devices();
    // A spec that matches nothing (PFILL_DEVICE=bogus) still lists the
    // devices, marks none and says why on stderr: this is where one looks.
    pfill::DeviceInfo chosen;
    chosen.index = -1;
    std::string problem;
    try {
      chosen = pfill::choose_device(*spec);
    } catch (const pfill::Error& e) {
      problem = e.what();
    }
    for (const auto& d : devices) {
      std::cout << (d.index == chosen.index ? "* " : "  ") << d.index << ": " << d.name << " [" << d.type << ", "
                << d.compute_units << " compute units, " << (d.global_memory >> 20) << " MiB] on " << d.platform
                << " (" << d.version << ")\n";
    }
    std::cout << "(* = used by default; set --device or PFILL_DEVICE to choose by index or name)\n";
    if (!problem.empty()) {
      std::cout.flush();
      std::cerr << "pfill: warning: " << problem << "\n";
      if (!spec->empty()) throw ExitStatus{kExitError};  // --device named here: an error; PFILL_DEVICE: a warning
    }
  });
}

}  // namespace pfill::cli
