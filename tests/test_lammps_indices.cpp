// The LAMMPS engine's indices and ids carried by the atoms themselves
// (issue 31: src/lammps/atom_indices.hpp; no rank keeps a book of every
// particle): the reads over the ranks (engine_reads.hpp) name an atom by
// the index it carries on whichever rank holds it, and name as lost the
// indices no rank holds any more (atoms LAMMPS dropped past its box,
// found by a bitmap reduced over the ranks). Atoms are deleted here behind
// the engine's back, which a fill never does: the wall keeps atoms inside.
// ctest runs this on one process and under `mpirun -np 2`.
#include <doctest/doctest.h>

#include "skip.hpp"

#ifdef PFILL_WITH_LAMMPS
#include <string>
#include <unordered_set>
#include <vector>

#include "lammps/atom_indices.hpp"
#include "lammps/engine_reads.hpp"
#include "lammps/new_atoms.hpp"
#include "pfill/lammps.hpp"

using namespace pfill;
using namespace pfill::lammps_engine;

TEST_CASE("lammps engine reads: atoms carry their index and id; the indices no rank holds are named lost") {
  if (!lammps_available()) PFILL_SKIP("LAMMPS is not available");
  LammpsSession s;
  s.commands(std::string("units lj\natom_style sphere\natom_modify map hash\nboundary f f f\n") +
             "region pf_box block 0 1 0 1 0 1\ncreate_box 1 pf_box\n" + atom_index_fix());
  // Six atoms across the box (so across the ranks' slabs), tags 3..8, indices 0..5, ids 100..105.
  NewAtoms atoms;
  for (int k = 0; k < 6; ++k) {
    Particle p;
    p.position = {0.1 + 0.15 * k, 0.1 + 0.15 * k, 0.1 + 0.15 * k};
    p.radius = 0.05;
    p.id = 100 + static_cast<uint64_t>(k);
    atoms.add(3 + k, p, 1.0);
  }
  REQUIRE(create_new_atoms(s, atoms, 3, 0) == 6);  // every rank passes all; each keeps its own
  EngineParams params;
  params.radius = 0.05;
  const Vec3 centre{0.5, 0.5, 0.5};
  CHECK(gather_flagged(s, 6, {}).empty());
  // Indices 1 and 4 (tags 4 and 7) deleted behind the engine's back: lost.
  s.delete_atoms({4, 7});
  CHECK(gather_flagged(s, 6, {}) == std::vector<size_t>{1, 4});
  const std::vector<Particle> all = gather_particles(s, 6, params, centre);
  REQUIRE(all.size() == 6);
  for (size_t i : {0, 2, 3, 5}) {
    CHECK(all[i].id == 100 + i);
    CHECK(all[i].position.x == doctest::Approx(0.1 + 0.15 * static_cast<double>(i)));
  }
  for (size_t i : {1, 4}) {
    CHECK(all[i].id == 0);
    CHECK(all[i].position.x == centre.x);
  }
  // A flag raised on rank 0 only names the flagged atom's index wherever it is now.
  std::unordered_set<int> flagged;
  if (s.rank() == 0) flagged = {6, 8};
  CHECK(gather_flagged(s, 6, flagged) == std::vector<size_t>{1, 3, 4, 5});
}

#else
TEST_CASE("lammps engine reads: atoms carry their index and id; the indices no rank holds are named lost") {
  PFILL_SKIP("this pfill was built without LAMMPS");
}
#endif
