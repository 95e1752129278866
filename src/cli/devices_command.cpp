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
    const pfill::DeviceInfo chosen = pfill::choose_device(*spec);
    for (const auto& d : devices) {
      std::cout << (d.index == chosen.index ? "* " : "  ") << d.index << ": " << d.name << " [" << d.type << ", "
                << d.compute_units << " compute units, " << (d.global_memory >> 20) << " MiB] on " << d.platform
                << " (" << d.version << ")\n";
    }
    std::cout << "(* = used by default; set --device or PFILL_DEVICE to choose by index or name)\n";
  });
}

}  // namespace pfill::cli
