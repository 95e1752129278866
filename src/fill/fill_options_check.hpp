// The fill's settings checked before any work (FillOptions): each bad one
// gets a one-line error naming it and its allowed range.
#pragma once
#include <cstddef>

#include "pfill/fill.hpp"

namespace pfill {

/// The most particles a fill takes on (about 30 GiB of device memory).
constexpr size_t kMaxParticles = 100'000'000;

/// Throws pfill::Error naming the first setting of `o` out of its range.
void check_fill_options(const FillOptions& o);

}  // namespace pfill
