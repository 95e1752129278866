/// @file device.hpp
/// @brief Finding and opening an OpenCL device: listing, choice by index or
/// name (the CLI's --device, the environment variable PFILL_DEVICE), and the
/// Device object that owns the context and the in-order command queue.
/// @note Built on the Khronos C++ bindings (<CL/opencl.hpp>) with their
/// exceptions off; every status goes through check_cl (device_error.hpp).
#pragma once
#include <CL/opencl.hpp>

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace pfill {

/// One OpenCL device as `pfill devices` shows it.
struct DeviceInfo {
  int index = 0;             ///< position in list_devices(), platform by platform
  std::string platform;      ///< platform name, e.g. "Portable Computing Language"
  std::string name;          ///< device name
  std::string type;          ///< "GPU", "CPU", "accelerator" or "other"
  std::string version;       ///< CL_DEVICE_VERSION
  unsigned compute_units = 0;
  size_t global_memory = 0;  ///< bytes
  size_t max_work_group = 0;
};

/// Every device of every platform, in platform order. Throws DeviceError
/// with the install hint when there is no OpenCL platform at all.
std::vector<DeviceInfo> list_devices();

/// Starts the OpenCL platforms (PoCL loads LLVM and starts its threads:
/// ~0.12 s on 2 cores) so that the first device then opens at once; run it
/// beside other start-up work, such as reading a mesh. Reports nothing: a
/// missing platform is the device's to say when it opens.
void preload_platforms();

/// The line shown when no OpenCL platform exists.
extern const char* const kNoPlatformMessage;

/// Picks a device: `spec` is a decimal index into list_devices() or a
/// case-insensitive substring of "platform device" names; an empty spec
/// falls back to $PFILL_DEVICE, then to the first GPU, then the first CPU,
/// then the first device. Throws pfill::Error naming the spec if none matches.
DeviceInfo choose_device(const std::string& spec = "");

/// Device time of the commands a profiling Device has noted, by kind, since
/// it opened (OpenCL event profiling: from each command's start to its end,
/// so a blocking read's wait for the kernels before it is not counted).
struct DeviceTimes {
  double kernel_seconds = 0;    ///< kernel launches
  double transfer_seconds = 0;  ///< reads and writes between host and device
  uint64_t kernels = 0, transfers = 0;
  std::map<std::string, double> by_kernel;  ///< kernel_seconds split by kernel name
};

/// An opened device: context and one in-order queue. Non-copyable, movable.
class Device {
 public:
  /// Opens the device choose_device(spec) names. With `profiling`, the queue
  /// records kernel times (bench only: it may slow launches).
  explicit Device(const std::string& spec = "", bool profiling = false);

  const DeviceInfo& info() const { return info_; }
  const cl::Context& context() const { return context_; }
  const cl::Device& device() const { return device_; }
  cl::CommandQueue& queue() { return queue_; }
  bool profiling() const { return profiling_; }

  /// A device buffer of `bytes` (at least 1); `what` names it in errors.
  cl::Buffer make_buffer(size_t bytes, const std::string& what, cl_mem_flags flags = CL_MEM_READ_WRITE) const;

  /// Blocks until every queued command is done.
  void finish();

  /// With profiling: keeps `event` (of a command enqueued with it) so that
  /// its time counts in times(); a kernel unless `transfer`. Completed
  /// events are folded into the totals now and then, so the list stays
  /// short. Without profiling: nothing. `kernel` names a kernel's launch
  /// (DeviceTimes::by_kernel).
  void note(const cl::Event& event, bool transfer, const std::string& kernel = {});
  /// The event to pass to an enqueue, to note() after it: a fresh one with
  /// profiling, else nullptr (no event made).
  cl::Event* profiled(cl::Event& event) { return profiling_ ? &event : nullptr; }
  /// Every noted command's time so far; waits for the queue to finish.
  DeviceTimes times();

 private:
  DeviceInfo info_;
  cl::Device device_;
  cl::Context context_;
  cl::CommandQueue queue_;
  bool profiling_ = false;
  struct Noted {
    cl::Event event;
    bool transfer;
    std::string kernel;
  };
  std::vector<Noted> noted_;  // not yet folded into totals_
  DeviceTimes totals_;
  void fold(bool wait);
};

}  // namespace pfill
