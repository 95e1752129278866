/// @file contact_network.hpp
/// @brief Finds the contact network (contacts.hpp) of a particle set: pairs
/// within a gap through a grid of cells (O(N)), the spheres touching a
/// mesh's surface through the Boundary, and its figures for the report.
#pragma once
#include <nlohmann/json.hpp>

#include "pfill/boundary.hpp"
#include "pfill/contacts.hpp"
#include "pfill/particles.hpp"

namespace pfill {

/// The default largest gap of a contact: 2% of the smaller radius (the
/// fill's own coordination, PackingMetrics::mean_coordination, counts
/// contacts within 2% of r).
constexpr double kDefaultContactGap = 0.02;

/// Every pair (a < b) whose gap d - r_a - r_b is at most gap_fraction x
/// min(r_a, r_b), with coordination per particle. gap_fraction in [0, 1];
/// throws pfill::Error otherwise. Cells of the largest contact distance,
/// O(N) for radii of one size.
ContactNetwork find_contacts(const ParticleSet& particles, double gap_fraction = kDefaultContactGap);

/// Adds the wall contacts: every sphere whose centre lies within
/// r (1 + gap_fraction) of the surface, with the closest point and the
/// outward normal there (exact distances through Embree). Parallel.
void find_wall_contacts(ContactNetwork& contacts, const ParticleSet& particles, const Boundary& boundary);

/// The network's figures for a report: pair and wall contact counts, the
/// gap bound, the largest and smallest gap (as fractions of the smaller
/// radius), the mean coordination, its histogram (count of spheres with 0,
/// 1, 2, ... contacts) and, with a boundary, the mean coordination by the
/// centre's distance from the wall in radii (bins [1,2), [2,3), ... the
/// last one open).
nlohmann::ordered_json contacts_report_json(const ContactNetwork& contacts, const ParticleSet& particles,
                                    const Boundary* boundary = nullptr);

}  // namespace pfill
