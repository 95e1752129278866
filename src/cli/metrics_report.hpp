// Printing of packing metrics, shared by `pfill fill` and `pfill check`
// (their JSON: pfill/fill_report.hpp).
#pragma once
#include <cstdio>
#include <string>

#include "cli/format.hpp"
#include "pfill/fill_report.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/radius_distribution.hpp"

namespace pfill::cli {

inline void print_metrics(std::FILE* out, const PackingMetrics& m) {
  std::fprintf(out, "  particles        %s\n", thousands(m.count).c_str());
  std::fprintf(out, "  packing fraction %.4f  (sphere volume / mesh volume %s)\n", m.packing_fraction,
               num(m.mesh_volume).c_str());
  std::fprintf(out, "  containment      %.2f%% of spheres inside (tolerance %.0f%% of r); largest penetration %.2f%% of r%s\n",
               100 * m.contained_share, 100 * m.containment_tolerance, 100 * m.max_penetration,
               m.centres_outside ? (", " + thousands(m.centres_outside) + " centres outside").c_str() : "");
  std::fprintf(out, "  overlaps         %s pairs; mean %.3g%%, largest %.3g%% of r; closest centres %.6f of r_i + r_j\n",
               thousands(m.overlapping_pairs).c_str(), 100 * m.mean_overlap, 100 * m.max_overlap, m.min_distance);
  if (m.largest_hole >= 0)
    std::fprintf(out, "  holes            largest empty hole %.3f r (%s)\n", m.largest_hole,
                 m.largest_hole >= 1 ? "a sphere fits there" : "no room for another sphere");
  std::fprintf(out, "  coordination     %.2f contacts per sphere\n", m.mean_coordination);
}

/// Unequal spheres: the law asked for, and how the radii follow it.
inline void print_radii_fit(std::FILE* out, const RadiusDistribution& d, const DistributionFit& f) {
  std::fprintf(out, "  radii            %s; overlaps and gaps of the smaller radius\n", d.describe().c_str());
  std::fprintf(out, "                   mean %s (asked %s), std %s (asked %s), skewness %.3f (asked %.3f)\n",
               num(f.mean).c_str(), num(d.mean()).c_str(), num(f.stddev).c_str(), num(d.stddev()).c_str(),
               f.skewness, d.skewness());
  std::string lines = f.describe(), line;
  for (char c : lines + "\n") {
    if (c != '\n') {
      line += c;
    } else if (!line.empty()) {
      std::fprintf(out, "                   %s\n", line.c_str());
      line.clear();
    }
  }
}

}  // namespace pfill::cli
