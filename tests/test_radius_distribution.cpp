// Sphere size distributions (radius_distribution.hpp): moments against
// closed forms and independent integrals, cdf and quantile, draws through
// the size classes, sieve curves from CSV files, and the errors of SPECs.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <string>

#include "mesh_writers.hpp"
#include "pfill/error.hpp"
#include "pfill/radius_distribution.hpp"

using namespace pfill;
using Law = RadiusDistribution::Law;

namespace {

double Phi(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// Mean, std and skewness of r(z), z standard normal cut to [lo, hi], by a
// midpoint rule (a resolution and method apart from the library's).
struct Moments {
  double mean, std, skew;
};
template <class R>
Moments midpoint(double lo, double hi, R r_of, int n = 200000) {
  double w = 0, m1 = 0;
  const double h = (hi - lo) / n;
  for (int i = 0; i < n; ++i) {
    const double z = lo + (i + 0.5) * h, p = std::exp(-0.5 * z * z);
    w += p, m1 += p * r_of(z);
  }
  const double mean = m1 / w;
  double m2 = 0, m3 = 0;
  for (int i = 0; i < n; ++i) {
    const double z = lo + (i + 0.5) * h, p = std::exp(-0.5 * z * z), x = r_of(z) - mean;
    m2 += p * x * x, m3 += p * x * x * x;
  }
  const double sd = std::sqrt(m2 / w);
  return {mean, sd, m3 / w / (sd * sd * sd)};
}

// n radii drawn as births draw them: a class by number share, then a radius in it.
std::vector<double> draw(const RadiusDistribution& d, size_t n, uint64_t seed, int bins = 16) {
  const std::vector<SizeClass> classes = d.size_classes(bins);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  std::vector<double> radii;
  for (size_t i = 0; i < n; ++i) {
    double u = uniform(rng), sum = 0;
    size_t k = 0;
    while (k + 1 < classes.size() && u > (sum += classes[k].number_share)) ++k;
    radii.push_back(d.draw_in_class(classes, k, uniform(rng)));
  }
  return radii;
}

std::string temp_file(const test::TempDir& dir, const std::string& name, const std::string& text) {
  const std::string path = dir.file(name);
  test::write_text(path, text);
  return path;
}
}  // namespace

TEST_CASE("uniform: moments in closed form, cdf and quantile") {
  const auto d = RadiusDistribution::parse("uniform:0.5,1.5");
  CHECK(d.law() == Law::Uniform);
  CHECK(!d.is_equal());
  CHECK(d.mean() == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(d.stddev() == doctest::Approx(1 / std::sqrt(12.0)).epsilon(1e-12));
  CHECK(std::abs(d.skewness()) < 1e-9);
  CHECK(d.mean_cube() == doctest::Approx((std::pow(1.5, 4) - std::pow(0.5, 4)) / 4).epsilon(1e-12));
  CHECK(d.min_radius() == 0.5);
  CHECK(d.max_radius() == 1.5);
  CHECK(d.cdf(0.75) == doctest::Approx(0.25));
  CHECK(d.quantile(0.25) == doctest::Approx(0.75));
  CHECK(d.rcp_gain() == doctest::Approx(0.0658 / std::sqrt(12.0)));
}

TEST_CASE("discrete: fractions by number and by volume") {
  const auto n = RadiusDistribution::parse("discrete:1:0.5,2:0.5");
  CHECK(n.mean() == doctest::Approx(1.5));
  CHECK(n.stddev() == doctest::Approx(0.5));
  CHECK(std::abs(n.skewness()) < 1e-12);
  CHECK(n.mean_cube() == doctest::Approx(4.5));
  CHECK(n.rcp_gain() == doctest::Approx(0.0658 / 3).epsilon(1e-9));
  CHECK(n.rcp_gain() == doctest::Approx(0.02193).epsilon(1e-3));
  const auto classes = n.size_classes();
  REQUIRE(classes.size() == 2);
  CHECK(classes[0].lo == 1);
  CHECK(classes[0].hi == 1);
  CHECK(classes[1].volume_share == doctest::Approx(8.0 / 9));

  const auto v = RadiusDistribution::parse("discrete:2:0.5,1:0.5", FractionBasis::Volume);
  const auto vc = v.size_classes();
  REQUIRE(vc.size() == 2);
  CHECK(vc[0].number_share == doctest::Approx(8.0 / 9));
  CHECK(vc[1].number_share == doctest::Approx(1.0 / 9));
  CHECK(vc[0].volume_share == doctest::Approx(0.5));
  CHECK(v.mean() == doctest::Approx(10.0 / 9));
  CHECK(v.draw_in_class(vc, 1, 0.7) == 2);

  // Duplicates merge, zero classes drop, fractions need not sum to 1.
  const auto m = RadiusDistribution::parse("discrete:1:1,1:1,3:2,5:0");
  CHECK(m.size_classes().size() == 2);
  CHECK(m.mean() == doctest::Approx(2));
  CHECK(RadiusDistribution::parse("discrete:2:7").is_equal());
}

TEST_CASE("lognormal: truncated moments against closed forms and an independent integral") {
  const double s = 0.2, k = RadiusDistribution::kTruncateSigmas;
  const auto d = RadiusDistribution::parse("lognormal:1,0.2");
  // E[r^j] of the cut law: exp(j^2 s^2 / 2) (Phi(k - j s) - Phi(-k - j s)) / (Phi(k) - Phi(-k)).
  auto raw = [&](int j) { return std::exp(j * j * s * s / 2) * (Phi(k - j * s) - Phi(-k - j * s)) / (Phi(k) - Phi(-k)); };
  CHECK(d.mean() == doctest::Approx(raw(1)).epsilon(1e-10));
  CHECK(d.mean_cube() == doctest::Approx(raw(3)).epsilon(1e-10));
  CHECK(d.stddev() == doctest::Approx(std::sqrt(raw(2) - raw(1) * raw(1))).epsilon(1e-8));
  const Moments m = midpoint(-k, k, [s](double z) { return std::exp(s * z); });
  CHECK(d.mean() == doctest::Approx(m.mean).epsilon(1e-8));
  CHECK(d.stddev() == doctest::Approx(m.std).epsilon(1e-7));
  CHECK(d.skewness() == doctest::Approx(m.skew).epsilon(1e-6));
  // Near the uncut law's: mean exp(s^2/2), d = sqrt(exp(s^2) - 1) = 0.202, S = 0.614.
  CHECK(d.mean() == doctest::Approx(std::exp(0.02)).epsilon(0.005));
  CHECK(d.stddev() / d.mean() == doctest::Approx(0.2).epsilon(0.05));
  CHECK(d.skewness() == doctest::Approx(0.6).epsilon(0.1 / 0.6));
  CHECK(d.skewness() < 0.614);  // the cut takes the long tail's share
  CHECK(d.min_radius() == doctest::Approx(std::exp(-0.6)));
  CHECK(d.max_radius() == doctest::Approx(std::exp(0.6)));
  CHECK(d.describe() == "lognormal, median 1, sigma of ln r 0.2 (cut at 3 sigma), radii 0.549..1.82");
}

TEST_CASE("normal: cut at 3 sigma and floored at a share of the mean") {
  const auto d = RadiusDistribution::parse("normal:1,0.1");
  CHECK(d.mean() == doctest::Approx(1).epsilon(1e-12));
  const Moments m = midpoint(-3, 3, [](double z) { return 1 + 0.1 * z; });
  CHECK(d.stddev() == doctest::Approx(m.std).epsilon(1e-7));
  CHECK(std::abs(d.skewness()) < 1e-9);
  // STD 0.5: 3 sigma below is past the floor, 0.05.
  const auto w = RadiusDistribution::parse("normal:1,0.5");
  CHECK(w.min_radius() == doctest::Approx(RadiusDistribution::kFloorShare));
  CHECK(w.max_radius() == doctest::Approx(2.5));
  const Moments f = midpoint(-1.9, 3, [](double z) { return 1 + 0.5 * z; });
  CHECK(w.mean() == doctest::Approx(f.mean).epsilon(1e-8));
  CHECK(w.stddev() == doctest::Approx(f.std).epsilon(1e-7));
  CHECK(w.skewness() == doctest::Approx(f.skew).epsilon(1e-5));
  CHECK(w.cdf(0.05) == 0);
  CHECK(w.describe().find("none below 5% of the mean") != std::string::npos);
}

TEST_CASE("quantile inverts cdf") {
  const test::TempDir dir("radii_roundtrip");
  const std::string csv = temp_file(dir, "pfill_test_sieve_roundtrip.csv", "0.5,0\n1,0.4\n2,1\n");
  for (const std::string spec : {"uniform:0.5,1.5", "lognormal:1,0.2", "lognormal:2,1", "normal:1,0.1",
                                 "normal:1,0.5", csv.c_str()}) {
    CAPTURE(spec);
    const auto d = RadiusDistribution::parse(spec);
    const double lo = d.min_radius(), hi = d.max_radius();
    for (int i = 1; i < 100; ++i) {
      const double r = lo + (hi - lo) * i / 100.0;
      CHECK(d.quantile(d.cdf(r)) == doctest::Approx(r).epsilon(1e-9));
      const double u = i / 100.0;
      CHECK(d.cdf(d.quantile(u)) == doctest::Approx(u).epsilon(1e-9));
    }
    CHECK(d.quantile(0) == doctest::Approx(lo));
    CHECK(d.quantile(1) == doctest::Approx(hi));
    CHECK(d.cdf(hi) == doctest::Approx(1));
  }
  const auto k = RadiusDistribution::parse("discrete:1:0.2,2:0.3,3:0.5");
  for (double r : {1.0, 2.0, 3.0}) CHECK(k.quantile(k.cdf(r)) == r);
  // A sieve curve's share at its smallest radius: an atom of the cdf.
  const std::string atom = temp_file(dir, "pfill_test_sieve_atom.csv", "0.5,0.1\n1,0.4\n2,1\n");
  const auto a = RadiusDistribution::parse(atom);
  const double w0 = a.cdf(0.5);
  CHECK(w0 == doctest::Approx(0.8 / 1.925));
  CHECK(a.cdf(0.4999) == 0);
  CHECK(a.quantile(0.5 * w0) == 0.5);
  CHECK(a.quantile(w0 + 0.01) > 0.5);
}

TEST_CASE("draws through the size classes reproduce the law") {
  const test::TempDir dir("radii_draws");
  const std::string csv = temp_file(dir, "pfill_test_sieve_draws.csv", "radius,passing\n0.5,0.1\n1,0.4\n2,1\n");
  uint64_t seed = 29;
  for (const std::string spec : {"uniform:0.5,1.5", "lognormal:1,0.2", "normal:1,0.5", "lognormal:1,0.6",
                                 csv.c_str(), "discrete:1:0.2,2:0.3,3:0.5"}) {
    CAPTURE(spec);
    const auto d = RadiusDistribution::parse(spec);
    const std::vector<double> radii = draw(d, 100000, seed++);
    const DistributionFit fit = compare_distribution(d, radii);
    CHECK(fit.distance < 0.01);
    CHECK(fit.mean == doctest::Approx(d.mean()).epsilon(0.01));
    CHECK(fit.stddev == doctest::Approx(d.stddev()).epsilon(0.02));
    double number = 0, volume = 0;
    for (const auto& c : fit.classes) {
      number += c.achieved_number, volume += c.achieved_volume;
      CHECK(c.achieved_number == doctest::Approx(c.requested_number).epsilon(0.05));
      CHECK(c.achieved_volume == doctest::Approx(c.requested_volume).epsilon(0.05));
    }
    CHECK(number == doctest::Approx(1));
    CHECK(volume == doctest::Approx(1));
    CHECK(fit.describe().find(fit.class_error ? "largest class error" : "KS distance") != std::string::npos);
  }
  // A law the radii do not follow is told apart.
  const auto d = RadiusDistribution::parse("lognormal:1,0.2");
  CHECK(compare_distribution(d, draw(RadiusDistribution::parse("lognormal:1.1,0.2"), 20000, 1)).distance > 0.1);
}

TEST_CASE("a sieve curve from a CSV file") {
  const test::TempDir dir("radii_sieve");
  // A header, CRLF ends, a comment, a share at the smallest radius.
  const std::string path =
      temp_file(dir, "pfill_test_sieve.csv", "radius,cumulative\r\n# sieved 2026\r\n0.5,0.1\r\n1,0.3\r\n2,0.8\r\n4,1\r\n");
  const auto d = RadiusDistribution::parse(path);
  CHECK(d.law() == Law::Sieve);
  CHECK(d.basis() == FractionBasis::Volume);
  const auto classes = d.size_classes();
  REQUIRE(classes.size() == 4);
  const double volume[] = {0.1, 0.2, 0.5, 0.2};
  double number = 0;
  for (size_t i = 0; i < 4; ++i) {
    CHECK(classes[i].volume_share == doctest::Approx(volume[i]));
    number += classes[i].number_share;
  }
  CHECK(number == doctest::Approx(1));
  CHECK(classes[0].lo == classes[0].hi);
  // Number per class ~ volume share x mean of r^-3 in the interval.
  auto per = [](double v, double lo, double hi) { return v * (1 / (lo * lo) - 1 / (hi * hi)) / (2 * (hi - lo)); };
  CHECK(classes[2].number_share / classes[1].number_share == doctest::Approx(per(0.5, 1, 2) / per(0.2, 0.5, 1)));
  CHECK(classes[0].number_share / classes[3].number_share == doctest::Approx(0.1 / 0.125 / per(0.2, 2, 4)));
  CHECK(d.min_radius() == 0.5);
  CHECK(d.max_radius() == 4);
  // Mean r^3 = the volume over the number: the volume shares weigh up.
  double cube = 0;
  for (size_t i = 1; i < 4; ++i) {
    const double lo = classes[i].lo, hi = classes[i].hi;
    cube += classes[i].number_share * (hi - lo) / ((1 / (lo * lo) - 1 / (hi * hi)) / 2);
  }
  CHECK(d.mean_cube() == doctest::Approx(cube + classes[0].number_share * 0.125).epsilon(1e-10));
  // Percent, semicolons.
  const std::string pct = temp_file(dir, "pfill_test_sieve_pct.csv", "0.5;0\n1;30\n2;100\n");
  const auto p = RadiusDistribution::parse(pct);
  REQUIRE(p.size_classes().size() == 2);
  CHECK(p.size_classes()[0].volume_share == doctest::Approx(0.3));
  CHECK(p.scaled(2).max_radius() == 4);
  CHECK(p.describe().find("sieve curve") == 0);
}

TEST_CASE("every bad SPEC is one line naming radii") {
  const test::TempDir dir("radii_bad");
  const std::string missing = dir.file("no_such_curve.csv");
  const std::string csv_bad[] = {"1,0\n2,0.5\n", "1,0\n0.5,1\n", "1,0.5\n2,0.4\n3,1\n", "1,0\nx,y\n2,1\n",
                                 "1,0\n2,1,3\n", "-1,0\n2,1\n", "1,0\n2,nan\n", "1,1\n", "", "1,0\n1,1\n"};
  std::vector<std::string> specs = {"",
                                    "lognormal:1",
                                    "lognormal:0,0.2",
                                    "lognormal:1,-0.1",
                                    "lognormal:1,nan",
                                    "lognormal:inf,0.2",
                                    "lognormal:1,0.2,3",
                                    "lognormal:1,1000",
                                    "normal:0,1",
                                    "normal:-1,0.1",
                                    "normal:1,-0.1",
                                    "normal:1,x",
                                    "uniform:2,1",
                                    "uniform:0,1",
                                    "uniform:-1,1",
                                    "uniform:1",
                                    "uniform:1,1e999",
                                    "discrete:1:0,2:0",
                                    "discrete:1:-0.5,2:1",
                                    "discrete:0:1",
                                    "discrete:1",
                                    "discrete:1:0.5,2",
                                    "discrete:a:b",
                                    "discrete:",
                                    "gamma:1,2",
                                    "lognormal",
                                    "1.5",
                                    missing};
  for (size_t i = 0; i < std::size(csv_bad); ++i)
    specs.push_back(temp_file(dir, "bad_" + std::to_string(i) + ".csv", csv_bad[i]));
  for (const std::string& spec : specs) {
    CAPTURE(spec);
    try {
      RadiusDistribution::parse(spec);
      FAIL("accepted");
    } catch (const Error& e) {
      const std::string what = e.what();
      CHECK(what.rfind("radii", 0) == 0);
      CHECK(what.find('\n') == std::string::npos);
    }
  }
  CHECK_THROWS_AS(parse_fraction_basis("mass"), Error);
  CHECK_THROWS_AS(RadiusDistribution::parse("uniform:1,2").scaled(0), Error);
  CHECK_THROWS_AS(RadiusDistribution::equal(-1), Error);
}

TEST_CASE("scaled: radii times s, shape kept, spec as given") {
  for (const std::string spec : {"uniform:0.5,1.5", "lognormal:1,0.2", "normal:1,0.2", "discrete:1:0.5,2:0.5"}) {
    CAPTURE(spec);
    const auto d = RadiusDistribution::parse(spec), s = d.scaled(2);
    CHECK(s.mean() == doctest::Approx(2 * d.mean()));
    CHECK(s.stddev() / s.mean() == doctest::Approx(d.stddev() / d.mean()));
    CHECK(s.skewness() == doctest::Approx(d.skewness()).epsilon(1e-6));
    CHECK(s.rcp_gain() == doctest::Approx(d.rcp_gain()));
    CHECK(s.spec() == spec);
    CHECK(s.quantile(0.3) == doctest::Approx(2 * d.quantile(0.3)));
  }
  CHECK(RadiusDistribution::parse("lognormal:1,0.2").scaled(2).describe().find("median 2,") != std::string::npos);
}

TEST_CASE("equal spheres and the fraction basis") {
  const auto e = RadiusDistribution::equal(2);
  CHECK(e.is_equal());
  CHECK(e.law() == Law::Equal);
  CHECK(e.mean() == 2);
  CHECK(e.stddev() == 0);
  CHECK(e.skewness() == 0);
  CHECK(e.rcp_gain() == 0);
  CHECK(e.mean_cube() == 8);
  CHECK(e.spec().empty());
  REQUIRE(e.size_classes(16).size() == 1);
  CHECK(e.draw_in_class(e.size_classes(), 0, 0.3) == 2);
  CHECK(RadiusDistribution().mean() == 1);
  CHECK(RadiusDistribution::parse("uniform:1,1").is_equal());
  CHECK(RadiusDistribution::parse("lognormal:3,0").is_equal());
  CHECK(RadiusDistribution::parse(" normal:1.5, 0 ").mean() == 1.5);
  CHECK(RadiusDistribution::parse("LogNormal:1,0.2").law() == Law::Lognormal);
  const DistributionFit fit = compare_distribution(e, {2, 2, 2});
  CHECK(fit.distance == 0);
  CHECK(fit.class_error);
  CHECK(compare_distribution(RadiusDistribution::parse("discrete:1:1,2:1"), {1, 1, 1, 2}).distance ==
        doctest::Approx(0.25));
  CHECK(parse_fraction_basis("volume") == FractionBasis::Volume);
  CHECK(std::string(to_string(FractionBasis::Number)) == "number");
  CHECK(RadiusDistribution::parse("discrete:1:3,2:1", FractionBasis::Volume).describe() ==
        "discrete, 2 radii by volume: 1 (75%), 2 (25%)");
}
