/// @file program.hpp
/// @brief OpenCL programs built once from the embedded kernels/*.cl with a
/// prelude of #defines, and the single function every launch goes through.
#pragma once
#include <CL/opencl.hpp>

#include <array>
#include <cstddef>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "pfill/device/device.hpp"
#include "pfill/device/device_error.hpp"

namespace pfill {

/// A kernel's parameter names in order, as its source declares them.
struct KernelSignature {
  std::vector<std::string> names;
  std::unordered_map<std::string_view, cl_uint> index;  // views into `names`
};

/// Each `__kernel` of an OpenCL C source (comments stripped) with its
/// parameter names: what Kernel::set binds by name.
std::map<std::string, std::shared_ptr<const KernelSignature>> kernel_signatures(const std::string& source);

/// A kernel with its name (for errors) and the work-group size it runs at.
class Kernel {
 public:
  Kernel() = default;
  Kernel(cl::Kernel kernel, std::string name, size_t work_group,
         std::shared_ptr<const KernelSignature> signature = nullptr);

  const std::string& name() const { return name_; }
  size_t work_group() const { return work_group_; }  ///< a power of two the device accepts
  cl::Kernel& handle() { return kernel_; }

  /// Sets argument `index`; the error names the kernel and the argument.
  /// A value equal to the one last set there is not set again (a step
  /// sets some 40 arguments and few change; each set costs the host time
  /// on some drivers). Call forget_args() when buffers are reallocated.
  template <typename T>
  void set_arg(cl_uint index, const T& value) {
    ArgBytes bytes;  // size 0: not cached (always set)
    if constexpr (std::is_base_of_v<cl::Memory, T>) {
      const cl_mem handle = value();
      bytes.size = sizeof handle;
      std::memcpy(bytes.data.data(), &handle, sizeof handle);
    } else if constexpr (std::is_trivially_copyable_v<T> && sizeof(T) <= sizeof(ArgBytes::data)) {
      bytes.size = sizeof value;
      std::memcpy(bytes.data.data(), &value, sizeof value);
    }
    if (bytes.size > 0 && index < last_args_.size() && last_args_[index] == bytes) return;
    check_cl(kernel_.setArg(index, value), "clSetKernelArg", name_ + " argument " + std::to_string(index));
    if (index >= last_args_.size()) last_args_.resize(index + 1);
    if (!last_args_[index].set) ++args_set_;
    last_args_[index] = bytes;
    last_args_[index].set = true;
  }
  /// Sets the argument the kernel's source names `name` (a device array
  /// passes its buffer); an unknown name throws, naming the kernel.
  template <typename T>
  Kernel& set(std::string_view name, const T& value) {
    if constexpr (has_buffer<T>::value)
      set_arg(arg_index(name), value.buffer());
    else
      set_arg(arg_index(name), value);
    return *this;
  }
  /// Sets the argument named `name` if the kernel declares one (shared
  /// binders: each kernel takes the ones it declares; launch() checks that
  /// none is left unset).
  template <typename T>
  Kernel& bind(std::string_view name, const T& value) {
    if (!signature_) return *this;
    const auto it = signature_->index.find(name);
    if (it == signature_->index.end()) return *this;
    if constexpr (has_buffer<T>::value)
      set_arg(it->second, value.buffer());
    else
      set_arg(it->second, value);
    return *this;
  }
  /// Throws unless every parameter was set since the last forget_args()
  /// (kernels with a known signature; launch() calls it).
  void require_all_set() const;
  /// Forgets the arguments last set, so that the next set_arg sets each.
  void forget_args() {
    last_args_.clear();
    args_set_ = 0;
  }
  /// Sets arguments 0, 1, ... in order.
  template <typename... Args>
  void set_args(const Args&... args) {
    cl_uint index = 0;
    (set_arg(index++, args), ...);
  }

 private:
  template <typename T, typename = void>
  struct has_buffer : std::false_type {};
  template <typename T>
  struct has_buffer<T, std::void_t<decltype(std::declval<const T&>().buffer())>> : std::true_type {};
  cl_uint arg_index(std::string_view name) const;

  cl::Kernel kernel_;
  std::string name_;
  size_t work_group_ = 1;
  std::shared_ptr<const KernelSignature> signature_;
  struct ArgBytes {
    size_t size = 0;
    std::array<unsigned char, 16> data{};
    bool set = false;
    bool operator==(const ArgBytes& o) const { return size == o.size && data == o.data; }
  };
  std::vector<ArgBytes> last_args_;
  size_t args_set_ = 0;  // arguments set since forget_args()
};

/// A number of local memory bytes as a kernel argument (for set_arg).
inline cl::LocalSpaceArg local_bytes(size_t bytes) { return cl::Local(bytes); }

/// A program built from embedded kernel files. The source is the prelude
/// (`#define NAME value` lines) followed by each file in order, so a file
/// may use functions of the files before it.
class Program {
 public:
  Program(Device& device, const std::vector<std::string>& files,
          const std::map<std::string, std::string>& defines, const std::string& options = "");

  /// The named kernel, with a work-group size: the largest power of two
  /// <= min(preferred, the kernel's and the device's limits).
  Kernel kernel(const std::string& name, size_t preferred_work_group = 128) const;

  const std::string& source() const { return source_; }

 private:
  cl::Program program_;
  std::string source_;
  std::map<std::string, std::shared_ptr<const KernelSignature>> signatures_;
  const Device* device_;
};

/// The largest power of two <= n (1 for n < 2): work-group sizes.
size_t floor_power_of_two(size_t n);

/// Enqueues `kernel` over `items` work-items (rounded up to whole
/// work-groups; kernels check their index against their count). Never
/// blocks. With `event`, the launch can be profiled. Errors name the kernel,
/// and an argument never set.
void launch(Device& device, Kernel& kernel, size_t items, cl::Event* event = nullptr);

}  // namespace pfill
