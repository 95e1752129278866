// The OpenCL device layer: listing, choice by spec, build errors, launches.
// The device comes from PFILL_DEVICE (PoCL in CI).
#include <doctest/doctest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "pfill/device/device.hpp"
#include "pfill/device/program.hpp"

using namespace pfill;

TEST_CASE("device: listing and choice by index and by name") {
  const auto devices = list_devices();
  REQUIRE(!devices.empty());
  for (size_t i = 0; i < devices.size(); ++i) CHECK(devices[i].index == static_cast<int>(i));
  const DeviceInfo first = choose_device("0");
  CHECK(first.name == devices[0].name);
  // A substring of the name, in another case, finds the same device.
  std::string part = devices[0].name.substr(0, 4);
  for (auto& c : part) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  CHECK(choose_device(part).index <= devices[0].index);
  CHECK_THROWS_WITH_AS(choose_device("no-such-device-xyz"), doctest::Contains("no OpenCL device matches"), Error);
  CHECK_THROWS_WITH_AS(choose_device("999"), doctest::Contains("no OpenCL device with index 999"), Error);
}

TEST_CASE("device: a program built with a prelude runs, and a launch scales values") {
  Device device;
  Program program(device, {"device_selftest.cl"}, {{"SCALE", "3.0f"}});
  Kernel k = program.kernel("scale_values", 64);
  CHECK(k.work_group() >= 1);
  CHECK((k.work_group() & (k.work_group() - 1)) == 0);
  const cl_uint n = 1000;  // not a multiple of the work-group: tests the bound check
  std::vector<float> x(n), y(n, -1.f);
  for (cl_uint i = 0; i < n; ++i) x[i] = static_cast<float>(i) * 0.5f;
  cl::Buffer dx = device.make_buffer(n * sizeof(float), "x");
  cl::Buffer dy = device.make_buffer(n * sizeof(float), "y");
  check_cl(device.queue().enqueueWriteBuffer(dx, CL_TRUE, 0, n * sizeof(float), x.data()), "write");
  k.set_args(dx, dy, n);
  launch(device, k, n);
  check_cl(device.queue().enqueueReadBuffer(dy, CL_TRUE, 0, n * sizeof(float), y.data()), "read");
  for (cl_uint i = 0; i < n; ++i) REQUIRE(y[i] == doctest::Approx(3.0 * x[i]));
}

TEST_CASE("device: a build error names the call, the status, the device and the log") {
  Device device;
  try {
    Program program(device, {"device_selftest.cl"}, {{"SCALE", "this is not C"}});
    FAIL("the build should have failed");
  } catch (const DeviceError& e) {
    const std::string what = e.what();
    CHECK(what.find("clBuildProgram") != std::string::npos);
    CHECK(what.find("CL_BUILD_PROGRAM_FAILURE") != std::string::npos);
    CHECK(what.find(device.info().name) != std::string::npos);
    CHECK(what.find("build log") != std::string::npos);
    CHECK(e.status() == CL_BUILD_PROGRAM_FAILURE);
  }
}

TEST_CASE("device: a missing kernel name is an error naming it") {
  Device device;
  Program program(device, {"device_selftest.cl"}, {});
  CHECK_THROWS_WITH_AS(program.kernel("no_such_kernel"), doctest::Contains("no_such_kernel"), DeviceError);
  CHECK(cl_status_name(-5) == "CL_OUT_OF_RESOURCES");
  CHECK(cl_status_name(-12345) == "CL_UNKNOWN_ERROR(-12345)");
}

TEST_CASE("device: kernel parameters are read from the source, comments and attributes aside") {
  const auto sigs = kernel_signatures(
      "/* __kernel void not_me(int a) */ // __kernel void nor_me(int b)\n"
      "__kernel __attribute__((reqd_work_group_size(PF_WG, 1, 1))) void step(\n"
      "    __global const float4* X, PF_FIELD_ARG sdf, const uint n) { f(a, b); }\n"
      "__kernel void empty(void) {}\n");
  REQUIRE(sigs.size() == 2);
  REQUIRE(sigs.count("step") == 1);
  CHECK(sigs.at("step")->names == std::vector<std::string>{"X", "sdf", "n"});
  CHECK(sigs.at("empty")->names.empty());
}

TEST_CASE("device: arguments bound by name; a wrong name, or one left unset, is an error naming it") {
  Device device;
  Program program(device, {"device_selftest.cl"}, {{"SCALE", "2.0f"}});
  Kernel k = program.kernel("scale_values", 64);
  const cl_uint n = 100;
  std::vector<float> x(n, 1.5f), y(n, 0.f);
  cl::Buffer dx = device.make_buffer(n * sizeof(float), "x");
  cl::Buffer dy = device.make_buffer(n * sizeof(float), "y");
  check_cl(device.queue().enqueueWriteBuffer(dx, CL_TRUE, 0, n * sizeof(float), x.data()), "write");
  CHECK_THROWS_WITH_AS(k.set("count", n), doctest::Contains("scale_values has no parameter named 'count'"), Error);
  k.set("y", dy).set("x", dx);  // any order
  CHECK_THROWS_WITH_AS(launch(device, k, n), doctest::Contains("parameter 'n' was not set"), Error);
  k.bind("not_declared", n).set("n", n);  // bind: only what the kernel declares
  launch(device, k, n);
  check_cl(device.queue().enqueueReadBuffer(dy, CL_TRUE, 0, n * sizeof(float), y.data()), "read");
  for (cl_uint i = 0; i < n; ++i) REQUIRE(y[i] == 3.0f);
  k.forget_args();  // after buffers change: everything must be set again
  CHECK_THROWS_WITH_AS(launch(device, k, n), doctest::Contains("was not set"), Error);
}
