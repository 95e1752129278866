// The text of --radii SPECs (radius_spec.cpp), for radius_distribution.cpp:
// errors are pfill::Error of one line starting `radii "SPEC": `, the setting's
// name, which with_flags() shows as --radii.
#pragma once
#include <string>
#include <vector>

#include "pfill/radius_distribution.hpp"

namespace pfill::radius_spec {

std::string trim_spaces(const std::string& s);
/// `s` cut at each `sep`, each piece trimmed.
std::vector<std::string> split(const std::string& s, char sep);
/// The whole of `text` as a number (NaN and inf included; callers refuse those).
bool read_number(const std::string& text, double& v);
[[noreturn]] void refuse(const std::string& spec, const std::string& what);
/// The numbers of "law:A,B": `count` of them, finite.
std::vector<double> law_numbers(const std::string& spec, const std::string& args, size_t count,
                                const std::string& form, const std::string& example);
/// "R1:F1,R2:F2,...": ascending radii and their number shares, summing to 1
/// (a radius given twice adds up its fractions; classes of fraction 0 are dropped).
void read_discrete(const std::string& spec, const std::string& args, FractionBasis basis, std::vector<double>& radii,
                   std::vector<double>& shares);
/// A sieve curve's rows: ascending radii, cumulative volume fractions
/// ending at exactly 1 (a curve ending at 100 is read as percent).
void read_sieve(const std::string& spec, const std::string& path, std::vector<double>& radii,
                std::vector<double>& cumulative);

}  // namespace pfill::radius_spec
