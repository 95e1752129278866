/// @file fill_report.hpp
/// @brief The figures of a fill and of a check as JSON: what `pfill fill
/// --report` writes, `pfill check --json` prints and the Python module's
/// `metrics` and `report` hold. One definition, so they always agree.
#pragma once
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "pfill/fill.hpp"
#include "pfill/packing_metrics.hpp"

namespace pfill {

/// The metrics as a JSON object: particles, mesh_volume, packing_fraction,
/// contained_share, containment_tolerance, centres_outside, max_penetration,
/// overlapping_pairs, mean_overlap, max_overlap, mean_coordination.
nlohmann::ordered_json metrics_json(const PackingMetrics& metrics);

/// Unequal spheres: the distribution asked for (spec, basis, moments, the
/// Desmond-Weeks gain) and achieved (moments, per-class shares, the KS or
/// largest class distance). A fill's report holds it (null for equal spheres).
nlohmann::ordered_json radii_json(const RadiusDistribution& asked, const DistributionFit& delivered);

/// One pass of a fill: its name, steps and seconds; profiled
/// (PFILL_PROFILE=1), also the device's seconds in kernels and transfers,
/// the host's (the rest) and the kernels' seconds by name.
nlohmann::ordered_json pass_json(const PassStats& pass);

/// The whole report of a fill: the mesh's name, the output file (may be
/// empty), the radius, the seed, the device, `metrics` (metrics_json), why
/// pass 1 stopped, the removals, the passes' steps and seconds, the
/// distance field, the birth sites and the warnings.
nlohmann::ordered_json fill_report_json(const FillResult& result, const std::string& mesh, uint64_t seed,
                                        const std::string& output = "");

}  // namespace pfill
