// The JSON forms of a fill's figures (include/pfill/fill_report.hpp).
#include "pfill/fill_report.hpp"

namespace pfill {

nlohmann::ordered_json metrics_json(const PackingMetrics& m) {
  return {{"particles", m.count},
          {"mesh_volume", m.mesh_volume},
          {"packing_fraction", m.packing_fraction},
          {"contained_share", m.contained_share},
          {"containment_tolerance", m.containment_tolerance},
          {"centres_outside", m.centres_outside},
          {"max_penetration", m.max_penetration},
          {"overlapping_pairs", m.overlapping_pairs},
          {"mean_overlap", m.mean_overlap},
          {"max_overlap", m.max_overlap},
          {"mean_coordination", m.mean_coordination},
          {"min_distance_over_contact", m.min_distance},
          {"largest_hole_over_r", m.largest_hole}};
}

nlohmann::ordered_json radii_json(const RadiusDistribution& d, const DistributionFit& f) {
  nlohmann::ordered_json classes = nlohmann::ordered_json::array();
  for (const DistributionFit::ClassFit& c : f.classes)
    classes.push_back({{"radii", {c.lo, c.hi}},
                       {"requested_number_share", c.requested_number},
                       {"number_share", c.achieved_number},
                       {"requested_volume_share", c.requested_volume},
                       {"volume_share", c.achieved_volume}});
  return {{"spec", d.spec()},
          {"by", to_string(d.basis())},
          {"law", d.describe()},
          {"requested", {{"mean", d.mean()}, {"stddev", d.stddev()}, {"skewness", d.skewness()},
                         {"min", d.min_radius()}, {"max", d.max_radius()}, {"rcp_gain", d.rcp_gain()}}},
          {"achieved", {{"mean", f.mean}, {"stddev", f.stddev}, {"skewness", f.skewness}}},
          {"distance", f.distance},
          {"classes", classes}};
}

nlohmann::ordered_json pass_json(const PassStats& p) {
  nlohmann::ordered_json j = {{"pass", p.name}, {"steps", p.steps}, {"seconds", p.seconds}};
  if (p.list_rebuilds >= 0) j["list_rebuilds"] = p.list_rebuilds;
  if (p.kernel_seconds < 0) return j;  // not profiled
  j["kernel_seconds"] = p.kernel_seconds;
  j["transfer_seconds"] = p.transfer_seconds;
  j["host_seconds"] = p.seconds - p.kernel_seconds - p.transfer_seconds;
  j["kernels"] = p.kernel_split;
  return j;
}

nlohmann::ordered_json fill_report_json(const FillResult& r, const std::string& mesh, uint64_t seed,
                                        const std::string& output) {
  nlohmann::ordered_json passes = nlohmann::ordered_json::array();
  for (const PassStats& p : r.passes) passes.push_back(pass_json(p));
  nlohmann::ordered_json sites = nlohmann::ordered_json::array();
  for (const BirthSite& s : r.sites)
    sites.push_back({{"position", {s.position.x, s.position.y, s.position.z}}, {"depth", s.depth}});
  return {{"mesh", mesh},
          {"output", output},
          {"radius", r.radius},
          {"seed", seed},
          {"device", r.device},
          {"metrics", metrics_json(r.metrics)},
          {"expected_count", r.expected},
          {"max_parts", r.max_parts},
          {"stop_signal", r.stop_signal},
          {"stop_reason", r.stop_reason},
          {"settle_reason", r.settle_reason},
          {"lost_outside", r.lost_outside},
          {"finish_removed", r.finish_removed},
          {"finish_forced", r.finish_forced},
          {"finish_rounds", r.finish_rounds},
          {"finish_near_rounds", r.finish_near_rounds},
          {"finish_largest_view", r.finish_largest_view},
          {"holes_filled", r.holes_filled},
          {"containment_moved", r.containment.moved},
          {"containment_removed", r.containment.removed},
          {"passes", passes},
          {"steps", r.steps},
          {"seconds", r.seconds},
          {"setup_seconds", r.setup_seconds},
          {"verify_seconds", r.verify_seconds},
          {"peak_memory_bytes", r.peak_memory},
          {"field", {{"spacing", r.field_spacing}, {"bytes", r.field_bytes}, {"seconds", r.field_seconds}}},
          {"sites", sites},
          {"parts", {{"closed", r.parts}, {"too_small", r.parts_too_small}}},
          {"radii", r.radii && r.radii_fit ? radii_json(*r.radii, *r.radii_fit) : nullptr},  // equal: `radius`
          {"warnings", r.warnings}};
}

}  // namespace pfill
