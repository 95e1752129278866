/// @file radius_distribution.hpp
/// @brief Sphere size distributions (`--radii SPEC`): what a polydisperse
/// fill draws its radii from, and how close a set of radii comes to it.
///
/// SPEC forms (radii in mesh units, or relative when the fill scales them
/// to a count):
///   uniform:MIN,MAX          radii uniform in [MIN, MAX] (by number)
///   lognormal:MEDIAN,SIGMA   ln r normal, sigma of ln r (by number),
///                            truncated at kTruncateSigmas
///   normal:MEAN,STD          r normal (by number), truncated at
///                            kTruncateSigmas and never below
///                            kFloorShare * MEAN
///   discrete:R1:F1,R2:F2,..  classes of one radius each, fractions by
///                            number (FractionBasis::Volume: by volume);
///                            normalised to sum to 1
///   FILE.csv                 a sieve curve: rows "radius,cumulative volume
///                            fraction" ascending (a header line allowed),
///                            the first fraction 0 (or taken as the smallest
///                            radius's share), the last 1; radii between two
///                            rows uniform by volume
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace pfill {

enum class FractionBasis { Number, Volume };

/// "number" or "volume".
const char* to_string(FractionBasis basis);
/// Parses "number" or "volume"; throws pfill::Error otherwise.
FractionBasis parse_fraction_basis(const std::string& text);

/// A class of radii the births draw by: radii in [lo, hi] (lo == hi for a
/// discrete class), with its share of the spheres by number and by volume.
struct SizeClass {
  double lo = 0, hi = 0;
  double number_share = 0;
  double volume_share = 0;
};

class RadiusDistribution {
 public:
  enum class Law { Equal, Uniform, Lognormal, Normal, Discrete, Sieve };
  static constexpr double kTruncateSigmas = 3;  ///< lognormal and normal are cut at this many sigmas either side
  static constexpr double kFloorShare = 0.05;   ///< normal: no radius below this share of the mean

  RadiusDistribution() = default;  ///< equal spheres of radius 1
  /// Equal spheres of radius r.
  static RadiusDistribution equal(double r);
  /// Parses a SPEC (above). `basis` says what discrete fractions are; a
  /// sieve curve is always by volume. Throws pfill::Error with one line
  /// naming what is wrong and the form expected.
  static RadiusDistribution parse(const std::string& spec, FractionBasis basis = FractionBasis::Number);

  Law law() const { return law_; }
  bool is_equal() const;                 ///< one radius only (Equal, or one discrete class)
  const std::string& spec() const { return spec_; }  ///< the text parsed ("" for equal())
  FractionBasis basis() const { return basis_; }
  /// The same law with every radius times `s` (> 0). spec() stays the text
  /// parsed; describe() shows the scaled numbers.
  RadiusDistribution scaled(double s) const;
  /// One line: "lognormal, median 1, sigma of ln r 0.2 (cut at 3 sigma), radii 0.549..1.82".
  std::string describe() const;

  // ---- moments of the radius by number (what one sphere drawn follows) ----
  double min_radius() const;  ///< the smallest radius drawn (after truncation)
  double max_radius() const;  ///< the largest radius drawn
  double mean() const;
  double stddev() const;
  double skewness() const;
  double mean_cube() const;   ///< E[r^3]: a sphere's mean volume is 4/3 pi mean_cube()
  /// Desmond & Weeks (PRE 90, 022204, 2014): random close packing gains
  /// 0.0658 d + 0.0857 S d^2 over equal spheres, d = stddev / mean, S the skewness.
  double rcp_gain() const;

  /// Number-weighted cumulative distribution of the radius.
  double cdf(double r) const;
  /// The radius at number quantile u in [0, 1].
  double quantile(double u) const;

  /// The classes births draw by: a discrete law's or a sieve curve's own
  /// (one per row interval), or for a continuous law `bins` classes of
  /// equal number share between quantiles. Equal: one class.
  std::vector<SizeClass> size_classes(int bins = 16) const;
  /// A radius of class `k` of size_classes(bins): the law's quantile inside
  /// the class at u in [0, 1) (lo for a discrete class).
  double draw_in_class(const std::vector<SizeClass>& classes, size_t k, double u) const;

 private:
  Law law_ = Law::Equal;
  std::string spec_;
  FractionBasis basis_ = FractionBasis::Number;
  double a_ = 1, b_ = 1;        ///< the law's two numbers (min,max / median,sigma / mean,std)
  std::vector<double> radii_;   ///< discrete classes or sieve rows, ascending
  std::vector<double> shares_;  ///< discrete: number shares (normalised); sieve: cumulative volume
  struct Impl;                  ///< the helpers of src/fill/radius_distribution.cpp
};

/// How close a set of radii comes to a distribution.
struct DistributionFit {
  /// Per class of size_classes() (for a continuous law: 8 quantile bins):
  /// requested and achieved shares by number and by volume.
  struct ClassFit {
    double lo = 0, hi = 0;
    double requested_number = 0, achieved_number = 0;
    double requested_volume = 0, achieved_volume = 0;
  };
  std::vector<ClassFit> classes;
  /// Continuous laws: Kolmogorov-Smirnov distance of the radii's empirical
  /// cdf against the law's (by number); discrete: the largest error of a
  /// class's share in the basis the fractions were given in.
  double distance = 0;
  /// true: `distance` is the largest class share error (discrete, equal),
  /// in `basis`; false: the Kolmogorov-Smirnov distance.
  bool class_error = false;
  FractionBasis basis = FractionBasis::Number;
  double mean = 0, stddev = 0, skewness = 0;  ///< of the radii given
  std::string describe() const;  ///< one line per class, then the distance
};

/// Compares `radii` with `d` (radii in the same units as d).
DistributionFit compare_distribution(const RadiusDistribution& d, const std::vector<double>& radii);

struct ParticleShare;  // particle_share.hpp

/// The same for a packing held in parts (issue 31): `radii` are this
/// process's own, the fit is of every process's together, the same on
/// each, with no radius gathered but those of the few bins of the law's
/// quantiles where the Kolmogorov-Smirnov distance may lie. Collective;
/// one process (share complete): the overload above.
DistributionFit compare_distribution(const RadiusDistribution& d, const std::vector<double>& radii,
                                     const ParticleShare& share);

}  // namespace pfill
