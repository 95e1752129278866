// The radii the finish's holes get, walked alike on every process (hole_radii.hpp).
#include "fill/hole_radii.hpp"

#include <algorithm>
#include <cstdint>

#include "fill/word_bits.hpp"

namespace pfill {

std::vector<double> radii_walked_alike(ParticleEngine& engine, const FinishView& view, const std::vector<double>& rooms,
                                       SizeDeficit& sizes, std::mt19937_64& rng) {
  std::vector<uint64_t> words;  // a hole: its process, its room
  for (double room : rooms) words.insert(words.end(), {static_cast<uint64_t>(view.region), bits_of(room)});
  if (!view.complete()) engine.gather_over_processes(words);
  std::vector<double> mine;
  for (size_t w = 0; w + 2 <= words.size(); w += 2) {
    const double r = sizes.take_within(double_of(words[w + 1]), rng);
    if (static_cast<int>(words[w]) == view.region) mine.push_back(r);
  }
  return mine;
}

std::vector<double> fit_radii_walked_alike(ParticleEngine& engine, const FinishView& view,
                                           const std::vector<Vec3>& fits, const std::vector<double>& rooms,
                                           SizeDeficit& sizes, std::mt19937_64& rng) {
  std::vector<uint64_t> words;  // a fit: its process, place and room
  for (size_t k = 0; k < fits.size(); ++k)
    words.insert(words.end(), {static_cast<uint64_t>(view.region), bits_of(fits[k].x), bits_of(fits[k].y),
                               bits_of(fits[k].z), bits_of(rooms[k])});
  if (!view.complete()) engine.gather_over_processes(words);
  std::vector<Vec3> placed;
  std::vector<double> placed_radii, mine;
  for (size_t w = 0; w + 5 <= words.size(); w += 5) {
    const Vec3 p(double_of(words[w + 1]), double_of(words[w + 2]), double_of(words[w + 3]));
    double room = double_of(words[w + 4]);
    for (size_t m = 0; m < placed.size(); ++m) room = std::min(room, length(placed[m] - p) - placed_radii[m]);
    const double r = sizes.take_within(room, rng);
    if (r > 0) placed.push_back(p), placed_radii.push_back(r);
    if (static_cast<int>(words[w]) == view.region) mine.push_back(r);
  }
  return mine;
}

}  // namespace pfill
