// A test case that cannot run here (a data folder, a client or a device
// feature missing) says so and ends; ctest reports it as skipped, not
// passed (tests/CMakeLists.txt: SKIP_REGULAR_EXPRESSION "pfill-skip:").
#pragma once
#include <iostream>

#define PFILL_SKIP(why)                                       \
  do {                                                        \
    std::cout << "pfill-skip: " << why << std::endl;          \
    return;                                                   \
  } while (0)
