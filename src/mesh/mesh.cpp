// Mesh-wide operations: welding, orientation flip, validation.
#include "pfill/mesh.hpp"

#include <cmath>
#include <cstring>
#include <unordered_map>

#include "pfill/error.hpp"

namespace pfill {
namespace {

struct CellKey {
  int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellKeyHash {
  size_t operator()(const CellKey& k) const {
    // Unsigned: the keys may be any 64-bit pattern, and signed overflow is undefined.
    return static_cast<size_t>(static_cast<uint64_t>(k.x) * 73856093u ^ static_cast<uint64_t>(k.y) * 19349663u ^
                               static_cast<uint64_t>(k.z) * 83492791u);
  }
};

// Bit pattern of a position, so that exact welding treats -0.0 and 0.0 alike.
CellKey exact_key(const Vec3& p) {
  auto bits = [](double v) {
    if (v == 0.0) v = 0.0;
    int64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  };
  return {bits(p.x), bits(p.y), bits(p.z)};
}

}  // namespace

size_t weld_vertices(Mesh& mesh, double tolerance) {
  const size_t n = mesh.positions.size();
  std::vector<uint32_t> remap(n);
  std::vector<Vec3> kept;
  kept.reserve(n);

  if (tolerance <= 0) {
    std::unordered_map<CellKey, uint32_t, CellKeyHash> first;
    first.reserve(n);
    for (size_t i = 0; i < n; ++i) {
      auto [it, inserted] = first.emplace(exact_key(mesh.positions[i]), static_cast<uint32_t>(kept.size()));
      if (inserted) kept.push_back(mesh.positions[i]);
      remap[i] = it->second;
    }
  } else {
    // Hash grid with cells of the tolerance: a match lies in one of 27 cells.
    std::unordered_multimap<CellKey, uint32_t, CellKeyHash> cells;
    cells.reserve(n);
    const double inv = 1.0 / tolerance;
    for (size_t i = 0; i < n; ++i) {
      const Vec3& p = mesh.positions[i];
      const CellKey c{static_cast<int64_t>(std::floor(p.x * inv)), static_cast<int64_t>(std::floor(p.y * inv)),
                      static_cast<int64_t>(std::floor(p.z * inv))};
      int64_t found = -1;
      for (int dz = -1; dz <= 1 && found < 0; ++dz)
        for (int dy = -1; dy <= 1 && found < 0; ++dy)
          for (int dx = -1; dx <= 1 && found < 0; ++dx) {
            auto range = cells.equal_range({c.x + dx, c.y + dy, c.z + dz});
            for (auto it = range.first; it != range.second; ++it)
              if (length(kept[it->second] - p) <= tolerance) { found = it->second; break; }
          }
      if (found < 0) {
        found = static_cast<int64_t>(kept.size());
        kept.push_back(p);
        cells.emplace(c, static_cast<uint32_t>(found));
      }
      remap[i] = static_cast<uint32_t>(found);
    }
  }

  for (Triangle& t : mesh.triangles)
    for (uint32_t& v : t) v = v < n ? remap[v] : v;  // out-of-range stays invalid for validate()

  // Drop vertices that no triangle uses, keeping the order of first use.
  std::vector<int64_t> used(kept.size(), -1);
  std::vector<Vec3> compact;
  compact.reserve(kept.size());
  for (Triangle& t : mesh.triangles)
    for (uint32_t& v : t) {
      if (v >= kept.size()) continue;
      if (used[v] < 0) {
        used[v] = static_cast<int64_t>(compact.size());
        compact.push_back(kept[v]);
      }
      v = static_cast<uint32_t>(used[v]);
    }
  const size_t removed = n - compact.size();
  mesh.positions = std::move(compact);
  return removed;
}

size_t remove_duplicate_triangles(Mesh& mesh) {
  // Key: the sorted corners; value: the first such triangle's index and
  // whether it was already cancelled by an oppositely wound twin.
  struct Seen {
    size_t first;
    bool even;  // the corners, as stored, are an even permutation of the sorted ones
    bool cancelled = false;
  };
  auto sorted = [](Triangle t, bool* even) {
    int swaps = 0;
    if (t[0] > t[1]) std::swap(t[0], t[1]), ++swaps;
    if (t[1] > t[2]) std::swap(t[1], t[2]), ++swaps;
    if (t[0] > t[1]) std::swap(t[0], t[1]), ++swaps;
    *even = swaps % 2 == 0;
    return t;
  };
  struct Hash {
    size_t operator()(const Triangle& t) const {
      return std::hash<uint64_t>()((static_cast<uint64_t>(t[0]) * 0x9E3779B97F4A7C15ull) ^
                                   (static_cast<uint64_t>(t[1]) << 21) ^ t[2]);
    }
  };
  std::unordered_map<Triangle, Seen, Hash> seen;
  seen.reserve(mesh.triangles.size());
  std::vector<bool> keep(mesh.triangles.size(), true);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    bool even = false;
    const Triangle key = sorted(mesh.triangles[t], &even);
    if (key[0] == key[1] || key[1] == key[2]) continue;  // degenerate: left as it is
    auto [it, inserted] = seen.emplace(key, Seen{t, even});
    if (inserted) continue;
    keep[t] = false;  // a repeat: the same face again
    if (it->second.even != even && !it->second.cancelled) {
      keep[it->second.first] = false;  // wound the other way: the two faces cancel
      it->second.cancelled = true;
    }
  }
  const size_t before = mesh.triangles.size();
  const bool colours = mesh.corner_colours.size() == 3 * before, uvs = mesh.corner_uvs.size() == 3 * before;
  const bool materials = mesh.triangle_materials.size() == before;
  size_t n = 0;
  for (size_t t = 0; t < before; ++t) {
    if (!keep[t]) continue;
    mesh.triangles[n] = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (colours) mesh.corner_colours[3 * n + k] = mesh.corner_colours[3 * t + k];
      if (uvs) mesh.corner_uvs[3 * n + k] = mesh.corner_uvs[3 * t + k];
    }
    if (materials) mesh.triangle_materials[n] = mesh.triangle_materials[t];
    ++n;
  }
  mesh.triangles.resize(n);
  if (colours) mesh.corner_colours.resize(3 * n);
  if (uvs) mesh.corner_uvs.resize(3 * n);
  if (materials) mesh.triangle_materials.resize(n);
  return before - n;
}

void flip_orientation(Mesh& mesh) {
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
    if (mesh.corner_colours.size() == 3 * mesh.triangles.size())
      std::swap(mesh.corner_colours[3 * t + 1], mesh.corner_colours[3 * t + 2]);
    if (mesh.corner_uvs.size() == 3 * mesh.triangles.size())
      std::swap(mesh.corner_uvs[3 * t + 1], mesh.corner_uvs[3 * t + 2]);
  }
}

void validate(const Mesh& mesh) {
  const std::string where = mesh.source.empty() ? std::string("mesh") : mesh.source;
  if (mesh.triangles.empty())
    throw Error(where + ": the mesh has no triangles; pfill needs a closed triangle surface");
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    if (!is_finite(mesh.positions[i]))
      throw Error(where + ": vertex " + std::to_string(i) +
                  " has a NaN or infinite coordinate; repair or re-export the mesh");
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (std::fabs(mesh.positions[i][k]) > kMaxCoordinate)
        throw Error(where + ": vertex " + std::to_string(i) + " has a coordinate of " +
                    std::to_string(mesh.positions[i][k]) + ", beyond the +-1e15 pfill computes with; rescale "
                    "the mesh");
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (uint32_t v : mesh.triangles[t])
      if (v >= mesh.positions.size())
        throw Error(where + ": triangle " + std::to_string(t) + " uses vertex index " + std::to_string(v) +
                    " but there are only " + std::to_string(mesh.positions.size()) + " vertices");
  const size_t corners = 3 * mesh.triangles.size();
  if (!mesh.corner_colours.empty() && mesh.corner_colours.size() != corners)
    throw Error(where + ": colour count does not match the triangles (internal error)");
  if (!mesh.corner_uvs.empty() && mesh.corner_uvs.size() != corners)
    throw Error(where + ": UV count does not match the triangles (internal error)");
  if (!mesh.triangle_materials.empty() && mesh.triangle_materials.size() != mesh.triangles.size())
    throw Error(where + ": material count does not match the triangles (internal error)");
  for (uint32_t m : mesh.triangle_materials)
    if (m >= mesh.materials.size())
      throw Error(where + ": a triangle uses material " + std::to_string(m) + " of " +
                  std::to_string(mesh.materials.size()));
  for (const Material& m : mesh.materials)
    if (m.texture >= static_cast<int>(mesh.textures.size()))
      throw Error(where + ": a material uses texture " + std::to_string(m.texture) + " of " +
                  std::to_string(mesh.textures.size()));
}

}  // namespace pfill
