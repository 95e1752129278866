// Listing, choosing and opening OpenCL devices.
#include "pfill/device/device.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "pfill/device/device_error.hpp"
#include "pfill/error.hpp"

namespace pfill {

const char* const kNoPlatformMessage = "no OpenCL platform found; install PoCL: apt-get install pocl-opencl-icd";

namespace {

std::vector<cl::Platform> platforms_or_throw() {
  std::vector<cl::Platform> platforms;
  const cl_int status = cl::Platform::get(&platforms);
  // The ICD loader answers CL_PLATFORM_NOT_FOUND_KHR (-1001) when none is installed.
  if (status == -1001 || (status == CL_SUCCESS && platforms.empty())) throw DeviceError(kNoPlatformMessage, status);
  check_cl(status, "clGetPlatformIDs");
  return platforms;
}

std::string type_name(cl_device_type type) {
  if (type & CL_DEVICE_TYPE_GPU) return "GPU";
  if (type & CL_DEVICE_TYPE_CPU) return "CPU";
  if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

template <cl_device_info Info, typename T>
T device_info(const cl::Device& device, const char* what) {
  T value{};
  check_cl(device.getInfo(Info, &value), "clGetDeviceInfo", what);
  return value;
}

// All devices with their handles, in the order of list_devices().
std::vector<std::pair<DeviceInfo, cl::Device>> enumerate() {
  std::vector<std::pair<DeviceInfo, cl::Device>> out;
  for (const cl::Platform& platform : platforms_or_throw()) {
    std::string platform_name;
    check_cl(platform.getInfo(CL_PLATFORM_NAME, &platform_name), "clGetPlatformInfo", "CL_PLATFORM_NAME");
    std::vector<cl::Device> devices;
    const cl_int status = platform.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    if (status == CL_DEVICE_NOT_FOUND) continue;
    check_cl(status, "clGetDeviceIDs", platform_name);
    for (const cl::Device& device : devices) {
      DeviceInfo info;
      info.index = static_cast<int>(out.size());
      info.platform = platform_name.c_str();  // drop a trailing NUL some drivers include
      info.name = device_info<CL_DEVICE_NAME, std::string>(device, "CL_DEVICE_NAME").c_str();
      info.version = device_info<CL_DEVICE_VERSION, std::string>(device, "CL_DEVICE_VERSION").c_str();
      info.type = type_name(device_info<CL_DEVICE_TYPE, cl_device_type>(device, "CL_DEVICE_TYPE"));
      info.compute_units = device_info<CL_DEVICE_MAX_COMPUTE_UNITS, cl_uint>(device, "CL_DEVICE_MAX_COMPUTE_UNITS");
      info.global_memory = device_info<CL_DEVICE_GLOBAL_MEM_SIZE, cl_ulong>(device, "CL_DEVICE_GLOBAL_MEM_SIZE");
      info.max_work_group = device_info<CL_DEVICE_MAX_WORK_GROUP_SIZE, size_t>(device, "CL_DEVICE_MAX_WORK_GROUP_SIZE");
      out.emplace_back(info, device);
    }
  }
  if (out.empty()) throw DeviceError("OpenCL platforms exist but have no device; install PoCL: apt-get install pocl-opencl-icd", CL_DEVICE_NOT_FOUND);
  return out;
}

std::pair<DeviceInfo, cl::Device> choose(const std::string& requested) {
  const auto all = enumerate();
  std::string spec = requested;
  if (spec.empty()) {
    const char* env = std::getenv("PFILL_DEVICE");
    if (env) spec = env;
  }
  if (spec.empty()) {
    for (const char* type : {"GPU", "CPU"})
      for (const auto& d : all)
        if (d.first.type == type) return d;
    return all.front();
  }
  if (std::all_of(spec.begin(), spec.end(), [](unsigned char c) { return std::isdigit(c); })) {
    const long index = std::strtol(spec.c_str(), nullptr, 10);
    if (index >= 0 && index < static_cast<long>(all.size())) return all[static_cast<size_t>(index)];
    throw Error("no OpenCL device with index " + spec + " (there are " + std::to_string(all.size()) +
                "); run `pfill devices` to list them");
  }
  for (const auto& d : all)
    if (lower(d.first.platform + " " + d.first.name).find(lower(spec)) != std::string::npos) return d;
  throw Error("no OpenCL device matches '" + spec + "'; run `pfill devices` to list them");
}

}  // namespace

void preload_platforms() {
  std::vector<cl::Platform> platforms;
  cl::Platform::get(&platforms);  // (its status is the device's to report, when it opens)
}

std::vector<DeviceInfo> list_devices() {
  std::vector<DeviceInfo> out;
  for (const auto& d : enumerate()) out.push_back(d.first);
  return out;
}

DeviceInfo choose_device(const std::string& spec) { return choose(spec).first; }

Device::Device(const std::string& spec, bool profiling) : profiling_(profiling) {
  auto chosen = choose(spec);
  info_ = chosen.first;
  device_ = chosen.second;
  cl_int status = CL_SUCCESS;
  context_ = cl::Context(device_, nullptr, nullptr, nullptr, &status);
  check_cl(status, "clCreateContext", info_.name);
  queue_ = cl::CommandQueue(context_, device_, profiling ? CL_QUEUE_PROFILING_ENABLE : 0, &status);
  check_cl(status, "clCreateCommandQueue", info_.name);
}

cl::Buffer Device::make_buffer(size_t bytes, const std::string& what, cl_mem_flags flags) const {
  cl_int status = CL_SUCCESS;
  cl::Buffer buffer(context_, flags, std::max<size_t>(bytes, 1), nullptr, &status);
  check_cl(status, "clCreateBuffer", what + " (" + std::to_string(bytes) + " bytes)");
  return buffer;
}

void Device::finish() { check_cl(queue_.finish(), "clFinish"); }

void Device::note(const cl::Event& event, bool transfer, const std::string& kernel) {
  if (!profiling_ || event() == nullptr) return;
  noted_.push_back({event, transfer, kernel});
  if (noted_.size() >= 4096) fold(false);
}

// Adds the noted events' times to the totals: all of them (after waiting
// for the queue) when `wait`, else the completed ones at the front (an
// in-order queue completes them in order).
void Device::fold(bool wait) {
  if (wait) finish();
  size_t done = 0;
  for (; done < noted_.size(); ++done) {
    const cl::Event& ev = noted_[done].event;
    if (!wait) {
      cl_int status = CL_QUEUED;
      check_cl(ev.getInfo(CL_EVENT_COMMAND_EXECUTION_STATUS, &status), "clGetEventInfo");
      if (status != CL_COMPLETE) break;
    }
    cl_ulong start = 0, end = 0;
    check_cl(ev.getProfilingInfo(CL_PROFILING_COMMAND_START, &start), "clGetEventProfilingInfo");
    check_cl(ev.getProfilingInfo(CL_PROFILING_COMMAND_END, &end), "clGetEventProfilingInfo");
    const double seconds = end > start ? static_cast<double>(end - start) * 1e-9 : 0.0;
    if (noted_[done].transfer) {
      totals_.transfer_seconds += seconds;
      ++totals_.transfers;
    } else {
      totals_.kernel_seconds += seconds;
      totals_.by_kernel[noted_[done].kernel] += seconds;
      ++totals_.kernels;
    }
  }
  noted_.erase(noted_.begin(), noted_.begin() + static_cast<std::ptrdiff_t>(done));
}

DeviceTimes Device::times() {
  if (profiling_) fold(true);
  return totals_;
}

}  // namespace pfill
