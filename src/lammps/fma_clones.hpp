// The LAMMPS engine's hot loops built twice, with and without the FMA
// instructions, the one to run chosen when the program loads (GCC's
// target_clones): physics.cl's explicit fma() compiles to a call into libm
// where the build may not assume FMA (4% of a finish step at 1e5 was that
// call), and to one instruction in the FMA build. fma() rounds once either
// way, and the library is built with -ffp-contract=off
// (cmake/pfill_layers.cmake), so GCC fuses no other a * b + c in the FMA
// build (it did without the flag: FIRE's records changed), and both
// builds compute the same bits.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PFILL_FMA_CLONES __attribute__((target_clones("fma", "default")))
#else
#define PFILL_FMA_CLONES
#endif
