// Program build from embedded kernel files, and the one launch function.
#include "pfill/device/program.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "pfill/embedded_kernels.hpp"

namespace pfill {

Kernel::Kernel(cl::Kernel kernel, std::string name, size_t work_group, std::shared_ptr<const KernelSignature> signature)
    : kernel_(std::move(kernel)), name_(std::move(name)), work_group_(work_group), signature_(std::move(signature)) {}

cl_uint Kernel::arg_index(std::string_view name) const {
  if (signature_) {
    const auto it = signature_->index.find(name);
    if (it != signature_->index.end()) return it->second;
  }
  throw Error("kernel " + name_ + " has no parameter named '" + std::string(name) + "'");
}

void Kernel::require_all_set() const {
  if (!signature_ || args_set_ == signature_->names.size()) return;
  for (size_t k = 0; k < signature_->names.size(); ++k)
    if (k >= last_args_.size() || !last_args_[k].set)
      throw Error("kernel " + name_ + ": parameter '" + signature_->names[k] + "' was not set before the launch");
}

namespace {

// `source` with its comments blanked (strings do not occur in kernels).
std::string without_comments(const std::string& source) {
  std::string out = source;
  for (size_t i = 0; i + 1 < out.size(); ++i) {
    if (out[i] == '/' && out[i + 1] == '/') {
      while (i < out.size() && out[i] != '\n') out[i++] = ' ';
    } else if (out[i] == '/' && out[i + 1] == '*') {
      const size_t end = out.find("*/", i + 2);
      const size_t stop = end == std::string::npos ? out.size() : end + 2;
      for (; i < stop; ++i)
        if (out[i] != '\n') out[i] = ' ';
      --i;
    }
  }
  return out;
}

bool is_word(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// The last identifier in `text` (a parameter's name).
std::string last_word(const std::string& text) {
  size_t end = text.size();
  while (end > 0 && !is_word(text[end - 1])) --end;
  size_t begin = end;
  while (begin > 0 && is_word(text[begin - 1])) --begin;
  return text.substr(begin, end - begin);
}

}  // namespace

std::map<std::string, std::shared_ptr<const KernelSignature>> kernel_signatures(const std::string& source) {
  const std::string text = without_comments(source);
  std::map<std::string, std::shared_ptr<const KernelSignature>> out;
  for (size_t at = text.find("__kernel"); at != std::string::npos; at = text.find("__kernel", at + 8)) {
    if ((at > 0 && is_word(text[at - 1])) || is_word(text[at + 8])) continue;
    // __kernel [__attribute__((...))] void NAME(PARAMS)
    size_t v = text.find("void", at);
    if (v == std::string::npos) break;
    const size_t open = text.find('(', v + 4);
    if (open == std::string::npos) break;
    const std::string name = last_word(text.substr(v + 4, open - v - 4));
    auto sig = std::make_shared<KernelSignature>();
    int depth = 0;
    size_t start = open + 1, k = open + 1;
    for (; k < text.size(); ++k) {
      const char c = text[k];
      if (c == '(') ++depth;
      if (c == ')' && depth-- == 0) break;
      if (c == ',' && depth == 0) {
        sig->names.push_back(last_word(text.substr(start, k - start)));
        start = k + 1;
      }
    }
    const std::string last = text.substr(start, k - start);
    if (last.find_first_not_of(" \t\n") != std::string::npos && last_word(last) != "void")
      sig->names.push_back(last_word(last));
    for (size_t i = 0; i < sig->names.size(); ++i) sig->index.emplace(sig->names[i], static_cast<cl_uint>(i));
    out.emplace(name, std::move(sig));  // the first definition of a name stands
    at = k;
  }
  return out;
}

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
  signatures_ = kernel_signatures(source_);
}

Kernel Program::kernel(const std::string& name, size_t preferred_work_group) const {
  cl_int status = CL_SUCCESS;
  cl::Kernel k(program_, name.c_str(), &status);
  check_cl(status, "clCreateKernel", name);
  size_t limit = 0;
  check_cl(k.getWorkGroupInfo(device_->device(), CL_KERNEL_WORK_GROUP_SIZE, &limit), "clGetKernelWorkGroupInfo", name);
  limit = std::min({limit, device_->info().max_work_group, preferred_work_group});
  const auto sig = signatures_.find(name);
  return Kernel(k, name, floor_power_of_two(limit), sig == signatures_.end() ? nullptr : sig->second);
}

size_t floor_power_of_two(size_t n) {
  size_t p = 1;
  while (p <= n / 2) p *= 2;
  return p;
}

void launch(Device& device, Kernel& kernel, size_t items, cl::Event* event) {
  kernel.require_all_set();
  const size_t wg = kernel.work_group();
  const size_t global = std::max<size_t>(1, (items + wg - 1) / wg) * wg;
  cl::Event own;  // a profiling device notes every launch (Device::times)
  if (!event) event = device.profiled(own);
  check_cl(device.queue().enqueueNDRangeKernel(kernel.handle(), cl::NullRange, cl::NDRange(global), cl::NDRange(wg),
                                               nullptr, event),
           "clEnqueueNDRangeKernel", kernel.name() + " (" + std::to_string(global) + " items, work-group " +
                                         std::to_string(wg) + ")");
  if (event) device.note(*event, false, kernel.name());
}

}  // namespace pfill
