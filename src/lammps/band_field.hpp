// The wall's field as the LAMMPS engine's step reads it (step_callback.hpp):
// the signed distance grid in bricks of 4^3 cells, each stored with the
// samples of its upper faces (5^3 floats), so that a cell's 8 corners lie
// within 128 bytes of each other, and neighbouring spheres read the same
// few cache lines and pages. In the flat grid a cell's corners lie in two
// slices tens of MiB apart: at spot -n 30000 reading them was a quarter of
// a LAMMPS step, most of it cache and TLB misses.
//
// One pass over the flat grid (kept by reference, never copied whole)
// marks each brick deep, when all its samples lie at or below -band (a
// sphere there cannot touch the wall), or gives it the next slot, in the
// bricks' order along x, then y, then z, so that bricks near in space are
// near in memory (slots taken on first touch were scattered: the sample's
// cache misses stayed). Slots are filled in chunks of 4,096 bricks, each
// when a sphere first reads one of its bricks: a rank holds the bricks
// near the wall in and around its own sub-domain, not the field. The same
// pass bounds the interpolant's slope.
//
// Or, from an ExactField (no flat grid anywhere: what `pfill fill
// --engine lammps` uses), each group of 4^3 bricks is looked at when a
// sphere first reads one of them: a brick whose centre lies deeper than
// the band plus its half diagonal is deep (the distance is 1-Lipschitz),
// the others get the next slots, in the group's order, and their samples
// computed from the mesh (the exact values the whole field holds near the
// wall), each sample of the group once. A rank then computes and holds
// only the bricks its own spheres reach, wherever its sub-domain moves.
// The index of bricks is in two levels: a word per group over the whole
// grid (1/4,096 of its samples), then a word per brick of the groups
// opened, so that a rank's index too grows with the bricks it reaches
// (one word per brick of the whole grid was 128 MiB a rank at the grid's
// largest, 2^31 samples).
//
// The wall's offset (EngineParams::wall_offset) is added to each sample
// as the kernels add it (a float sum), so a moved wall needs no shifted
// copy either.
#pragma once
#ifdef PFILL_WITH_LAMMPS
#include <cstdint>
#include <memory>
#include <vector>

#include "pfill/exact_field.hpp"
#include "pfill/grid.hpp"

namespace pfill {
namespace lammps_engine {

class BandField {
 public:
  /// `field` must outlive this; `offset` is added to every sample (as a
  /// float); bricks all of whose samples are at most -band are deep.
  BandField(const ScalarGrid& field, double offset, double band);
  /// The same over `exact`'s grid (it must outlive this), samples computed on first use.
  BandField(const ExactField& exact, double offset, double band);
  BandField(const BandField&) = delete;
  BandField& operator=(const BandField&) = delete;
  ~BandField();

  const ScalarGrid& grid() const { return field_; }
  /// A bound on the interpolant's slope (with the offset added).
  double lipschitz() const { return lipschitz_; }
  /// The field's value at p (plus the offset) and its gradient into g:
  /// physics.cl's pf_sdf_sample, bit for bit, from the bricks.
  double sample(double px, double py, double pz, double* g);
  /// As `sample`, unless the cell at p (clamped into the grid) lies in a
  /// deep brick: then false (the sample there is at most -band).
  /// `slot`: the brick's slot (the same on every rank), for `prefetch`.
  bool sample_unless_deep(double px, double py, double pz, double* g, double& phi, int32_t& slot);
  /// Hints that p, last seen in brick `slot` (from sample_unless_deep; < 0:
  /// none), will be sampled soon: the cache lines of its cell's corners.
  void prefetch(double px, double py, double pz, int32_t slot) const;
  /// Bytes held in bricks (the index of bricks included; from an
  /// ExactField, the bricks computed, in chunks of 2 MiB allocated as they fill).
  size_t bytes() const;
  /// Bricks given samples so far (the deep ones hold none).
  size_t bricks() const { return bricks_.size(); }

 private:
  struct Cell {
    int i, j, k;
    double tx, ty, tz;
  };
  Cell cell_at(double px, double py, double pz) const;
  size_t brick_index(int bi, int bj, int bk) const {
    return static_cast<size_t>(bi) + static_cast<size_t>(nb_[0]) * (bj + static_cast<size_t>(nb_[1]) * bk);
  }
  size_t group_index(int bi, int bj, int bk) const {
    return static_cast<size_t>(bi / kGroup) +
           static_cast<size_t>(ng_[0]) * (bj / kGroup + static_cast<size_t>(ng_[1]) * (bk / kGroup));
  }
  static size_t in_group(int bi, int bj, int bk) {
    return static_cast<size_t>(bi % kGroup + kGroup * (bj % kGroup + kGroup * (bk % kGroup)));
  }
  /// The brick holding cell (i, j, k): its slot, or kDeep (its group looked at first, from an ExactField).
  int32_t brick(int i, int j, int k) {
    const int bi = i / kCells, bj = j / kCells, bk = k / kCells;
    const int32_t g = groups_[group_index(bi, bj, bk)];
    return g == kUnseen ? open_group(bi, bj, bk) : slots_[static_cast<size_t>(g) + in_group(bi, bj, bk)];
  }
  /// Brick (bi, bj, bk)'s entry of the index, its group given entries (kDeep) first.
  int32_t& entry(int bi, int bj, int bk);
  /// From an ExactField: the group of brick (bi, bj, bk) given slots and
  /// samples, or marked deep; returns that brick's slot or kDeep.
  int32_t open_group(int bi, int bj, int bk);
  /// Brick b's samples (clamped into the grid past its upper faces), offset added.
  void read_brick(size_t b, float* v) const;
  /// A slot's samples; its chunk filled on first use.
  const float* corners(const Cell& c, int32_t slot) {
    return slot_values(slot) + (c.i % kCells) + kSide * ((c.j % kCells) + kSide * (c.k % kCells));
  }
  const float* slot_values(int32_t slot) {
    const std::unique_ptr<float[], FreeChunk>& c = chunks_[static_cast<size_t>(slot >> kChunkShift)];
    if (!c) fill_chunk(slot >> kChunkShift);
    return c.get() + (slot & kChunkMask) * kBrickFloats;
  }
  void fill_chunk(int32_t chunk);
  static float* allocate_chunk();

  static constexpr int kCells = 4, kSide = kCells + 1;  // a brick's cells and samples a side
  static constexpr int kBrickFloats = 128;              // kSide^3 = 125, padded to 512 bytes
  static constexpr int kChunkShift = 12, kChunkMask = (1 << kChunkShift) - 1;  // 4,096 bricks (2 MiB) a chunk
  static constexpr int kGroup = 4;  // bricks a side looked at together (from an ExactField)
  static constexpr int32_t kDeep = -1, kUnseen = -2;

  struct FreeChunk {
    void operator()(float* p) const;
  };
  const ScalarGrid& field_;  // the flat grid, or the ExactField's grid (no values)
  const ExactField* exact_ = nullptr;
  float offset_;
  double band_;
  int nb_[3] = {0, 0, 0};  // bricks a side
  int ng_[3] = {0, 0, 0};  // groups a side
  double lipschitz_ = 0;
  std::vector<int32_t> groups_;  // per group: kUnseen, or where its kGroup^3 entries start in slots_
  std::vector<int32_t> slots_;   // per brick of the groups given entries: kDeep or its slot
  std::vector<int32_t> bricks_;  // per slot: its brick
  std::vector<std::unique_ptr<float[], FreeChunk>> chunks_;  // null until first used
};

}  // namespace lammps_engine
}  // namespace pfill
#endif
