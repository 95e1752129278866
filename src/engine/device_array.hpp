// A typed array on the device: its element count, growth that keeps the
// first elements (a copy on the device), zeroing, and the host transfers,
// each error naming what the array holds.
#pragma once
#include <CL/opencl.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "pfill/device/device.hpp"
#include "pfill/device/device_error.hpp"

namespace pfill {

template <typename T>
class DeviceArray {
 public:
  DeviceArray(Device& device, std::string what) : device_(&device), what_(std::move(what)) {}

  size_t size() const { return size_; }
  const cl::Buffer& buffer() const { return buffer_; }

  /// A new buffer of `count` elements (at least 1); its contents are
  /// undefined unless `zeroed`. Kernels holding the old one must be given
  /// the new (Kernel::forget_args: a freed handle may be reused).
  void reset(size_t count, bool zeroed = false) {
    size_ = std::max<size_t>(count, 1);
    buffer_ = device_->make_buffer(size_ * sizeof(T), what_);
    if (zeroed) zero();
  }
  /// reset(count, zeroed), keeping the first `keep` elements.
  void grow(size_t count, size_t keep, bool zeroed = false) {
    const cl::Buffer old = buffer_;
    reset(count, zeroed);
    if (keep > 0)
      check_cl(device_->queue().enqueueCopyBuffer(old, buffer_, 0, 0, keep * sizeof(T)), "clEnqueueCopyBuffer", what_);
  }
  /// Elements [first, first + count) set to `value` (all by default: zero).
  void fill(T value = T{}, size_t first = 0, size_t count = npos) {
    count = std::min(count, size_ - first);
    check_cl(device_->queue().enqueueFillBuffer(buffer_, value, first * sizeof(T), count * sizeof(T)),
             "clEnqueueFillBuffer", what_);
  }
  void zero() { fill(T{}); }
  /// Elements from `first` on from the host.
  void write(size_t first, const std::vector<T>& values, bool blocking = true) {
    if (values.empty()) return;
    cl::Event ev;
    check_cl(device_->queue().enqueueWriteBuffer(buffer_, blocking ? CL_TRUE : CL_FALSE, first * sizeof(T),
                                                 values.size() * sizeof(T), values.data(), nullptr,
                                                 device_->profiled(ev)),
             "clEnqueueWriteBuffer", what_);
    device_->note(ev, true);
  }
  /// The first `count` elements into `out` (resized).
  void read(size_t count, std::vector<T>& out, bool blocking = true) const {
    out.resize(count);
    if (count == 0) return;
    cl::Event ev;
    check_cl(device_->queue().enqueueReadBuffer(buffer_, blocking ? CL_TRUE : CL_FALSE, 0, count * sizeof(T), out.data(),
                                                nullptr, device_->profiled(ev)),
             "clEnqueueReadBuffer", what_);
    device_->note(ev, true);
  }
  std::vector<T> read(size_t count) const {
    std::vector<T> out;
    read(count, out);
    return out;
  }

  static constexpr size_t npos = static_cast<size_t>(-1);

 private:
  Device* device_;
  std::string what_;
  cl::Buffer buffer_;
  size_t size_ = 0;
};

}  // namespace pfill
