// The text of --radii SPECs (radius_spec.hpp): numbers, discrete classes
// and sieve curves, read and checked, every error one line naming `radii`.
#include "fill/radius_spec.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "fill/short_number.hpp"
#include "pfill/error.hpp"

namespace pfill::radius_spec {
namespace {

constexpr const char* kRows = "expected rows \"radius,cumulative volume fraction\" by ascending radius, ending at 1";

}  // namespace

std::string trim_spaces(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  size_t start = 0;
  for (size_t i = 0; i <= s.size(); ++i)
    if (i == s.size() || s[i] == sep) {
      out.push_back(trim_spaces(s.substr(start, i - start)));
      start = i + 1;
    }
  return out;
}

bool read_number(const std::string& text, double& v) {
  if (text.empty()) return false;
  char* end = nullptr;
  v = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

[[noreturn]] void refuse(const std::string& spec, const std::string& what) {
  throw Error("radii \"" + excerpt(spec, 60) + "\": " + what);
}

std::vector<double> law_numbers(const std::string& spec, const std::string& args, size_t count,
                                const std::string& form, const std::string& example) {
  const std::string hint = "expected " + form + " (e.g. " + example + ")";
  const std::vector<std::string> parts = split(args, ',');
  if (parts.size() != count) refuse(spec, hint);
  std::vector<double> v(count);
  for (size_t i = 0; i < count; ++i) {
    if (!read_number(parts[i], v[i])) refuse(spec, "\"" + excerpt(parts[i]) + "\" is not a number; " + hint);
    if (!std::isfinite(v[i])) refuse(spec, excerpt(parts[i]) + " is not a finite number; " + hint);
  }
  return v;
}

void read_sieve(const std::string& spec, const std::string& path, std::vector<double>& radii,
                std::vector<double>& cumulative) {
  std::ifstream in(path);
  if (!in)
    refuse(spec, std::string("cannot read the sieve curve (") + std::strerror(errno) +
                     "); give the path of a CSV file of rows \"radius,cumulative volume fraction\"");
  std::string line;
  bool first = true;  // the first line of content may be a header
  for (int n = 1; std::getline(in, line); ++n) {
    line = trim_spaces(line);
    if (line.empty() || line[0] == '#') continue;
    const char sep = line.find(',') != std::string::npos ? ',' : line.find(';') != std::string::npos ? ';' : '\t';
    const std::vector<std::string> f = split(line, sep);
    const std::string at = "line " + std::to_string(n) + ": ";
    double r = 0, c = 0;
    const bool header_allowed = first;
    first = false;
    if (header_allowed && !read_number(f[0], r)) continue;  // a header line
    if (f.size() != 2) refuse(spec, at + std::to_string(f.size()) + " fields; " + kRows);
    if (!read_number(f[0], r) || !read_number(f[1], c))
      refuse(spec, at + "\"" + excerpt(line) + "\" is not two numbers; " + kRows);
    if (!std::isfinite(r) || !std::isfinite(c)) refuse(spec, at + "a number is not finite; " + kRows);
    if (!(r > 0)) refuse(spec, at + "radius " + short_number(r) + " is not positive; " + kRows);
    if (c < 0) refuse(spec, at + "cumulative fraction " + short_number(c) + " is negative; " + kRows);
    if (!radii.empty() && !(r > radii.back()))
      refuse(spec, at + "radius " + short_number(r) + " is not above the previous row's " +
                       short_number(radii.back()) + "; sort the rows by radius, each radius once");
    if (!cumulative.empty() && c < cumulative.back())
      refuse(spec, at + "cumulative fraction " + short_number(c) + " falls below the previous row's " +
                       short_number(cumulative.back()) + "; a sieve curve never decreases");
    radii.push_back(r);
    cumulative.push_back(c);
  }
  if (radii.size() < 2) refuse(spec, "the sieve curve has fewer than two rows; " + std::string(kRows));
  // Percent is taken when the curve ends at 100.
  double end = cumulative.back();
  if (std::abs(end - 100) <= 1e-4) {
    for (double& c : cumulative) c /= 100;
    end = cumulative.back();
  }
  if (std::abs(end - 1) > 1e-6)
    refuse(spec, "the sieve curve ends at " + short_number(end) + "; its last cumulative fraction must be 1 (or 100 "
                 "for percent)");
  for (double& c : cumulative) c = std::min(c, 1.0);
  cumulative.back() = 1;
}


void read_discrete(const std::string& spec, const std::string& args, FractionBasis basis, std::vector<double>& radii,
                   std::vector<double>& shares) {
  const std::string hint = "expected discrete:R1:F1,R2:F2,... (e.g. discrete:1:0.7,2:0.3)";
  std::vector<std::pair<double, double>> rows;
  for (const std::string& item : split(args, ',')) {
    const std::vector<std::string> rf = split(item, ':');
    double r = 0, f = 0;
    if (rf.size() != 2) refuse(spec, "\"" + excerpt(item) + "\" is not R:F; " + hint);
    if (!read_number(rf[0], r) || !read_number(rf[1], f))
      refuse(spec, "\"" + excerpt(item) + "\" is not two numbers R:F; " + hint);
    if (!std::isfinite(r) || !std::isfinite(f)) refuse(spec, "\"" + excerpt(item) + "\" is not finite; " + hint);
    if (!(r > 0)) refuse(spec, "radius " + short_number(r) + " is not positive; " + hint);
    if (f < 0) refuse(spec, "fraction " + short_number(f) + " is negative; " + hint);
    rows.emplace_back(r, f);
  }
  std::sort(rows.begin(), rows.end());
  for (const auto& [r, f] : rows) {
    if (!radii.empty() && radii.back() == r) {
      shares.back() += f;  // a radius given twice: its fractions add up
    } else if (f > 0) {       // a class of no share is never drawn
      radii.push_back(r);
      shares.push_back(f);
    }
  }
  if (radii.empty()) refuse(spec, "every fraction is 0; give at least one class a positive fraction");
  const double big = radii.back();
  if (basis == FractionBasis::Volume)
    for (size_t i = 0; i < radii.size(); ++i) shares[i] /= std::pow(radii[i] / big, 3);
  double total = 0;
  for (double s : shares) total += s;
  for (double& s : shares) s /= total;
}

}  // namespace pfill::radius_spec
