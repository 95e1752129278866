// The contact options `pfill fill` and `pfill contacts` share
// (--contacts, --gap, --pairs), and what they do after a fill: find the
// network in the final particles, add it to the output and the report.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "pfill/boundary.hpp"
#include "pfill/contact_network.hpp"
#include "pfill/particle_io.hpp"

namespace pfill::cli {

struct ContactArgs {
  bool contacts = false;            ///< find the contact network (fill: --contacts)
  double gap = kDefaultContactGap;  ///< largest gap, fraction of the smaller radius
  std::string pairs;                ///< CSV of the contacts; implies contacts
  bool wanted() const { return contacts || !pairs.empty(); }
};

/// Adds --contacts (when `with_flag`), --contact-gap and --pairs to `cmd`;
/// --contact-gap and --pairs in `details_group` (fill: shown by --help-all).
void add_contact_options(CLI::App* cmd, ContactArgs& args, bool with_flag, const std::string& details_group = "Options");

/// The network of `particles` (wall contacts too when a boundary is given),
/// its --pairs CSV written, and its report section.
struct ContactResult {
  std::unique_ptr<ContactNetwork> network;
  nlohmann::ordered_json report;
};
ContactResult find_and_write_contacts(const ContactArgs& args, const ParticleSet& particles,
                                      const Boundary* boundary);

/// `pfill check --pairs P.csv`: every pair listed in a contacts CSV (as
/// --pairs writes it; wall rows skipped) is checked against `particles` (by
/// id): its gap within `gap` x the smaller radius (to float rounding).
/// Misses are appended to `misses`; returns the figures as JSON.
nlohmann::ordered_json verify_pairs(const ParticleSet& particles, const std::string& path, double gap,
                                    std::vector<std::string>& misses);

/// One summary line: "contacts  M pairs (gap <= 2% of the smaller radius), mean coordination X, W at the wall".
void print_contacts_line(std::FILE* out, const ContactNetwork& network, bool with_wall);

}  // namespace pfill::cli
