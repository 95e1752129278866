// Program build from embedded kernel files, and the one launch function.
#include "pfill/device/program.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "pfill/embedded_kernels.hpp"

namespace pfill {

Kernel::Kernel(cl::Kernel kernel, std::string name, size_t work_group)
    : kernel_(std::move(kernel)), name_(std::move(name)), work_group_(work_group) {}

Program::Program(Device& device, const std::vector<std::string>& files,
                 const std::map<std::string, std::string>& defines, const std::string& options)
    : device_(&device) {
  for (const auto& [name, value] : defines) source_ += "#define " + name + " " + value + "\n";
  // PFILL_KERNEL_DIR: read the kernel files from that folder instead of the
  // embedded copies (developers' runs of another revision's kernels beside
  // this one's, e.g. bench_variants "kernels=/tmp/old" "")
  const char* kernel_dir = std::getenv("PFILL_KERNEL_DIR");
  for (const std::string& file : files) {
    std::string text;
    if (kernel_dir != nullptr && *kernel_dir != '\0') {
      const std::string path = std::string(kernel_dir) + "/" + file;
      std::ifstream in(path);
      if (!in) throw Error("cannot read " + path + " (PFILL_KERNEL_DIR); unset it to use the built-in kernels");
      std::ostringstream all;
      all << in.rdbuf();
      text = all.str();
    } else {
      try {
        text = embedded_kernel_source(file);
      } catch (const std::exception& e) {
        throw Error(std::string(e.what()) + "; is kernels/" + file + " in the source tree?");
      }
    }
    source_ += "#line 1 \"" + file + "\"\n";
    source_ += text;
    source_ += "\n";
  }
  cl_int status = CL_SUCCESS;
  program_ = cl::Program(device.context(), source_, false, &status);
  check_cl(status, "clCreateProgramWithSource");
  // PFILL_CL_OPTIONS: extra build options for every program (developers'
  // runs of kernel variants side by side, e.g. "-DPF_X=0";
  // bench/bench_variants)
  std::string all_options = options;
  if (const char* extra = std::getenv("PFILL_CL_OPTIONS")) all_options += std::string(all_options.empty() ? "" : " ") + extra;
  const cl_int build = program_.build(std::vector<cl::Device>{device.device()}, all_options.c_str());
  if (build != CL_SUCCESS) {
    std::string log;
    program_.getBuildInfo(device.device(), CL_PROGRAM_BUILD_LOG, &log);
    std::string files_list;
    for (const auto& f : files) files_list += (files_list.empty() ? "" : ", ") + f;
    check_cl(build, "clBuildProgram",
             files_list + " on " + device.info().name + " (options '" + all_options + "'); build log:\n" + log);
  }
}

Kernel Program::kernel(const std::string& name, size_t preferred_work_group) const {
  cl_int status = CL_SUCCESS;
  cl::Kernel k(program_, name.c_str(), &status);
  check_cl(status, "clCreateKernel", name);
  size_t limit = 0;
  check_cl(k.getWorkGroupInfo(device_->device(), CL_KERNEL_WORK_GROUP_SIZE, &limit), "clGetKernelWorkGroupInfo", name);
  limit = std::min({limit, device_->info().max_work_group, preferred_work_group});
  return Kernel(k, name, floor_power_of_two(limit));
}

size_t floor_power_of_two(size_t n) {
  size_t p = 1;
  while (p <= n / 2) p *= 2;
  return p;
}

void launch(Device& device, Kernel& kernel, size_t items, cl::Event* event) {
  const size_t wg = kernel.work_group();
  const size_t global = std::max<size_t>(1, (items + wg - 1) / wg) * wg;
  check_cl(device.queue().enqueueNDRangeKernel(kernel.handle(), cl::NullRange, cl::NDRange(global), cl::NDRange(wg),
                                               nullptr, event),
           "clEnqueueNDRangeKernel", kernel.name() + " (" + std::to_string(global) + " items, work-group " +
                                         std::to_string(wg) + ")");
}

}  // namespace pfill
