// What a kernel launch costs on the fill's device, apart from the kernel's
// work: a step launches three kernels (insert_cells, pair_forces,
// advance), and at a few thousand particles each has only tens of
// microseconds of work, so launches and the wake-up of the device's other
// threads set the step's time there (docs/benchmarks.md, issue 32). Times,
// in an in-order queue drained every 72 launches as a fill's batch is:
//   - an empty kernel, one work-group and one a compute unit;
//   - a kernel with a fixed amount of work a group (--work-us, ~40 us:
//     pair_forces' block at 4,000 particles on 2 cores), one group and one
//     a compute unit, and so how far the groups run side by side.
// Usage: bench_launch [--device INDEX|NAME] [--work-us US] [--launches N] [--json FILE]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "pfill/device/device.hpp"
#include "pfill/device/device_error.hpp"
#include "pfill/error.hpp"

using namespace pfill;

namespace {

// A chain of dependent multiply-adds: `work` of them take a fixed time on one core.
const char* kSource = R"CLC(
__kernel __attribute__((reqd_work_group_size(1, 1, 1))) void spin(__global float* x, const uint work) {
  const uint g = get_global_id(0);
  float a = x[g];
  for (uint i = 0; i < work; ++i) a = fma(a, 0.999f, 0.001f);
  x[g] = a;
}
)CLC";

struct Launcher {
  Device& device;
  cl::Kernel kernel;
  cl::Buffer values;
  int launches;

  // Mean wall microseconds a launch of `groups` groups of `work` steps,
  // the best of three rounds (the machine's load swings).
  double microseconds(size_t groups, cl_uint work) {
    check_cl(kernel.setArg(0, values), "clSetKernelArg", "spin x");
    check_cl(kernel.setArg(1, work), "clSetKernelArg", "spin work");
    double best = 1e30;
    for (int round = 0; round < 3; ++round) {
      const auto start = std::chrono::steady_clock::now();
      for (int k = 0; k < launches; ++k) {
        check_cl(device.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(groups), cl::NDRange(1)),
                 "clEnqueueNDRangeKernel", "spin");
        if (k % 72 == 71) device.finish();  // a fill's batch: 24 steps of 3 launches, then a read
      }
      device.finish();
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      best = std::min(best, 1e6 * s / launches);
    }
    return best;
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::string device_spec, json_path;
  double work_us = 40;
  int launches = 3000;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_launch: %s needs a value\n", arg.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--device") device_spec = next();
    else if (arg == "--work-us") work_us = std::stod(next());
    else if (arg == "--launches") launches = std::max(72, std::stoi(next()));
    else if (arg == "--json") json_path = next();
    else {
      std::fprintf(stderr, "usage: bench_launch [--device INDEX|NAME] [--work-us US] [--launches N] [--json FILE]\n");
      return 2;
    }
  }
  try {
    Device device(device_spec);
    const size_t units = std::max<size_t>(1, device.info().compute_units);
    cl::Program program(device.context(), kSource);
    if (program.build({device.device()}) != CL_SUCCESS) throw Error("bench_launch: the spin kernel did not build");
    Launcher l{device, cl::Kernel(program, "spin"), device.make_buffer(units * sizeof(cl_float), "values"), launches};
    std::printf("device: %s (%s), %zu compute units; %d launches, drained every 72\n", device.info().name.c_str(),
                device.info().platform.c_str(), units, launches);

    const double empty_one = l.microseconds(1, 0), empty_all = l.microseconds(units, 0);
    // The work a group: scaled from a timed single group to about work_us.
    cl_uint work = 1000;
    for (int tries = 0; tries < 4; ++tries) {
      const double per_group = std::max(0.1, l.microseconds(1, work) - empty_one);
      work = static_cast<cl_uint>(std::clamp(work * work_us / per_group, 10.0, 1e8));
    }
    const double busy_one = l.microseconds(1, work), busy_all = l.microseconds(units, work);
    const double group_us = busy_one - empty_one;
    // Side by side, `units` groups take one group's time plus the launch.
    const double speedup = units * group_us / std::max(1e-9, busy_all - empty_one);
    std::printf("empty kernel:        %7.1f us a launch (1 group), %7.1f us (%zu groups)\n", empty_one, empty_all, units);
    std::printf("%5.1f us a group:     %7.1f us a launch (1 group), %7.1f us (%zu groups; side by side %.1f)\n", group_us,
                busy_one, busy_all, units, empty_one + group_us);
    std::printf("the %zu groups ran %.2f times as fast as one after another (%zu: all side by side)\n", units, speedup,
                units);
    if (!json_path.empty()) {
      nlohmann::json j = {{"benchmark", "bench_launch"},
                          {"device", device.info().name},
                          {"platform", device.info().platform},
                          {"compute_units", units},
                          {"launches", launches},
                          {"empty_us_one_group", empty_one},
                          {"empty_us_all_groups", empty_all},
                          {"group_work_us", group_us},
                          {"busy_us_one_group", busy_one},
                          {"busy_us_all_groups", busy_all},
                          {"parallel_speedup", speedup}};
      std::ofstream(json_path) << j.dump(2) << "\n";
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_launch: %s\n", e.what());
    return 1;
  }
  return 0;
}
