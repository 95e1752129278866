// Sphere size distributions (radius_distribution.hpp): the SPEC forms, the
// moments of the truncated laws and the classes births draw by. Errors name
// the setting `radii` as their first word, so with_flags() shows it as
// --radii (radius_spec.hpp reads the text).
#include "pfill/radius_distribution.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "fill/radius_spec.hpp"
#include "fill/short_number.hpp"
#include "pfill/error.hpp"

namespace pfill {
using namespace radius_spec;
namespace {

using Law = RadiusDistribution::Law;
constexpr double kSqrt2 = 1.4142135623730951;
constexpr const char* kForms =
    "expected uniform:MIN,MAX, lognormal:MEDIAN,SIGMA, normal:MEAN,STD, discrete:R1:F1,R2:F2,... or a sieve "
    "curve FILE.csv";

double density(double z) { return 0.3989422804014327 * std::exp(-0.5 * z * z); }
double lower(double z) { return 0.5 * std::erfc(-z / kSqrt2); }  // Phi(z)
double upper(double z) { return 0.5 * std::erfc(z / kSqrt2); }   // 1 - Phi(z), exact in the upper tail

// Phi^-1(p) for p in (0, 0.5]: Acklam's rational approximation (1e-9),
// polished by two Halley steps on erfc (to about 1e-15).
double inverse_lower(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  if (!(p > 0)) return -40;
  double x;
  if (p < 0.02425) {
    const double q = std::sqrt(-2 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  }
  for (int i = 0; i < 2; ++i) {
    const double u = (lower(x) - p) * 2.5066282746310002 * std::exp(0.5 * x * x);
    x -= u / (1 + 0.5 * x * u);
  }
  return x;
}

// 8-point Gauss-Legendre on [-1, 1].
const double kNode[] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
const double kWeight[] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

// The integral of g over [lo, hi] in `panels` equal panels.
template <class G>
double gauss(double lo, double hi, int panels, G g) {
  const double h = (hi - lo) / panels;
  double sum = 0;
  for (int p = 0; p < panels; ++p) {
    const double mid = lo + (p + 0.5) * h, half = 0.5 * h;
    for (int k = 0; k < 4; ++k) sum += kWeight[k] * half * (g(mid - half * kNode[k]) + g(mid + half * kNode[k]));
  }
  return sum;
}

std::string g3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}
}  // namespace

// The private helpers: the continuous laws in their own variable t (r for
// uniform, z = the standard normal variable for lognormal and normal).
struct RadiusDistribution::Impl {
  using RD = RadiusDistribution;
  static double t_lo(const RD& d) {
    if (d.law_ == Law::Uniform) return d.a_;
    if (d.law_ == Law::Normal) return std::max(-kTruncateSigmas, (kFloorShare - 1) * d.a_ / d.b_);
    return -kTruncateSigmas;
  }
  static double t_hi(const RD& d) { return d.law_ == Law::Uniform ? d.b_ : kTruncateSigmas; }
  static double r_of(const RD& d, double t) {
    return d.law_ == Law::Uniform ? t : d.law_ == Law::Lognormal ? d.a_ * std::exp(d.b_ * t) : d.a_ + d.b_ * t;
  }
  static double t_of(const RD& d, double r) {
    if (d.law_ == Law::Uniform) return r;
    if (d.law_ == Law::Lognormal) return r > 0 ? std::log(r / d.a_) / d.b_ : -HUGE_VAL;
    return (r - d.a_) / d.b_;
  }
  // The unnormalised integral of f(r(t)) over t in [t1, t2].
  template <class F>
  static double integrate(const RD& d, double t1, double t2, F f) {
    if (d.law_ == Law::Uniform) return gauss(t1, t2, 4, [&](double t) { return f(t); });
    return gauss(t1, t2, 32, [&](double t) { return f(r_of(d, t)) * density(t); });
  }
  static double cdf_t(const RD& d, double t) {
    const double lo = t_lo(d), hi = t_hi(d);
    t = std::clamp(t, lo, hi);
    if (d.law_ == Law::Uniform) return (t - lo) / (hi - lo);
    const double mass = lower(hi) - lower(lo);
    return t <= 0 ? (lower(t) - lower(lo)) / mass : 1 - (upper(t) - upper(hi)) / mass;
  }
  static double t_of_u(const RD& d, double u) {
    const double lo = t_lo(d), hi = t_hi(d);
    u = std::clamp(u, 0.0, 1.0);
    if (d.law_ == Law::Uniform) return lo + u * (hi - lo);
    const double mass = lower(hi) - lower(lo), p = lower(lo) + u * mass;
    const double z = p <= 0.5 ? inverse_lower(p) : -inverse_lower(upper(hi) + (1 - u) * mass);
    return std::clamp(z, lo, hi);
  }

  // Sieve: class 0 is the smallest radius's own share (radii_[0] exactly),
  // class i the interval [radii_[i-1], radii_[i]], uniform by volume there,
  // so by number its density is ~ r^-3.
  static std::vector<double> sieve_numbers(const RD& d) {
    const double s = d.radii_.back();  // in units of the largest radius: no overflow
    std::vector<double> w(d.radii_.size());
    w[0] = d.shares_[0] / std::pow(d.radii_[0] / s, 3);
    for (size_t i = 1; i < w.size(); ++i) {
      const double lo = d.radii_[i - 1] / s, hi = d.radii_[i] / s;
      w[i] = (d.shares_[i] - d.shares_[i - 1]) * (1 / (lo * lo) - 1 / (hi * hi)) / (2 * (hi - lo));
    }
    double total = 0;
    for (double x : w) total += x;
    for (double& x : w) x /= total;
    return w;
  }
  // The number share of [lo, r] within an interval of density ~ r^-3, and its inverse.
  static double within(double lo, double hi, double r) {
    r = std::clamp(r, lo, hi);
    return (1 - (lo / r) * (lo / r)) / (1 - (lo / hi) * (lo / hi));
  }
  static double within_inverse(double lo, double hi, double w) {
    return std::clamp(lo / std::sqrt(1 - w * (1 - (lo / hi) * (lo / hi))), lo, hi);
  }
  // E[f(r)] by number within a sieve interval: r = lo (hi/lo)^t, dr = r L dt,
  // so the weight r^-3 dr is ~ (r/lo)^-2 dt.
  template <class F>
  static double sieve_mean(double lo, double hi, F f) {
    const double L = std::log(hi / lo);
    auto weight = [L](double t) { return std::exp(-2 * t * L); };
    return gauss(0, 1, 8, [&](double t) { return f(lo * std::exp(t * L)) * weight(t); }) / gauss(0, 1, 8, weight);
  }

  // E[f(r)] by number.
  template <class F>
  static double expect(const RD& d, F f) {
    switch (d.law_) {
      case Law::Equal: return f(d.a_);
      case Law::Discrete: {
        double sum = 0;
        for (size_t i = 0; i < d.radii_.size(); ++i) sum += d.shares_[i] * f(d.radii_[i]);
        return sum;
      }
      case Law::Sieve: {
        const std::vector<double> w = sieve_numbers(d);
        double sum = w[0] * f(d.radii_[0]);
        for (size_t i = 1; i < w.size(); ++i)
          if (w[i] > 0) sum += w[i] * sieve_mean(d.radii_[i - 1], d.radii_[i], f);
        return sum;
      }
      default:
        return integrate(d, t_lo(d), t_hi(d), f) / integrate(d, t_lo(d), t_hi(d), [](double) { return 1.0; });
    }
  }
};

const char* to_string(FractionBasis basis) { return basis == FractionBasis::Volume ? "volume" : "number"; }

FractionBasis parse_fraction_basis(const std::string& text) {
  if (text == "number") return FractionBasis::Number;
  if (text == "volume") return FractionBasis::Volume;
  throw Error("radii_by \"" + excerpt(text) + "\": expected number or volume (what discrete:R:F fractions "
              "count)");
}

RadiusDistribution RadiusDistribution::equal(double r) {
  if (!(r > 0) || !std::isfinite(r)) throw Error("radii: an equal radius must be a positive number, not " +
                                                 short_number(r));
  RadiusDistribution d;
  d.a_ = d.b_ = r;
  return d;
}

RadiusDistribution RadiusDistribution::parse(const std::string& text, FractionBasis basis) {
  RadiusDistribution d;
  d.spec_ = text;
  d.basis_ = basis;
  const std::string spec = trim_spaces(text);
  if (spec.empty()) refuse(text, kForms);
  std::string tail = spec.size() >= 4 ? spec.substr(spec.size() - 4) : "";
  for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const size_t colon = spec.find(':');
  const std::string args = colon == std::string::npos ? "" : spec.substr(colon + 1);
  std::string name = trim_spaces(spec.substr(0, colon));
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (tail == ".csv") {
    d.law_ = Law::Sieve;
    d.basis_ = FractionBasis::Volume;
    read_sieve(text, spec, d.radii_, d.shares_);
  } else if (name == "uniform") {
    const auto v = law_numbers(text, args, 2, "uniform:MIN,MAX", "uniform:0.5,1.5");
    if (!(v[0] > 0)) refuse(text, "MIN " + short_number(v[0]) + " is not a positive radius; expected uniform:MIN,MAX "
                                  "with 0 < MIN <= MAX (e.g. uniform:0.5,1.5)");
    if (v[0] > v[1]) refuse(text, "MIN " + short_number(v[0]) + " is above MAX " + short_number(v[1]) +
                                      "; write uniform:MIN,MAX with MIN <= MAX");
    d.law_ = v[0] == v[1] ? Law::Equal : Law::Uniform;
    d.a_ = v[0], d.b_ = v[1];
  } else if (name == "lognormal" || name == "normal") {
    const bool log = name == "lognormal";
    const std::string form = log ? "lognormal:MEDIAN,SIGMA" : "normal:MEAN,STD";
    const auto v = law_numbers(text, args, 2, form, log ? "lognormal:1,0.2" : "normal:1,0.1");
    if (!(v[0] > 0))
      refuse(text, std::string(log ? "MEDIAN " : "MEAN ") + short_number(v[0]) + " is not a positive radius; "
                   "expected " + form + " (e.g. " + (log ? "lognormal:1,0.2)" : "normal:1,0.1)"));
    if (v[1] < 0)
      refuse(text, std::string(log ? "SIGMA (the std of ln r) " : "STD ") + short_number(v[1]) +
                       " is negative; give 0 or more");
    d.law_ = v[1] == 0 ? Law::Equal : log ? Law::Lognormal : Law::Normal;  // no spread: equal spheres
    d.a_ = v[0], d.b_ = v[1];
  } else if (name == "discrete") {
    d.law_ = Law::Discrete;
    read_discrete(text, args, basis, d.radii_, d.shares_);
  } else {
    refuse(text, "unknown law \"" + excerpt(name) + "\"; " + kForms);
  }
  const double lo = d.min_radius(), hi = d.max_radius(), cube = d.mean_cube();
  if (!(lo > 0) || !std::isfinite(hi) || !(cube > 0) || !std::isfinite(cube))
    refuse(text, "its radii reach " + short_number(lo) + ".." + short_number(hi) +
                     ", past what a double holds; choose a narrower law");
  return d;
}

bool RadiusDistribution::is_equal() const { return law_ == Law::Equal || min_radius() == max_radius(); }

RadiusDistribution RadiusDistribution::scaled(double s) const {
  if (!(s > 0) || !std::isfinite(s)) throw Error("radii: a scale must be a positive number, not " + short_number(s));
  RadiusDistribution d = *this;  // spec_ stays the text the user gave; describe() shows the scaled numbers
  d.a_ *= s;
  if (law_ != Law::Lognormal) d.b_ *= s;  // a lognormal's sigma is of ln r: a scale leaves it
  for (double& r : d.radii_) r *= s;
  return d;
}

std::string RadiusDistribution::describe() const {
  const std::string range = ", radii " + g3(min_radius()) + ".." + g3(max_radius());
  switch (law_) {
    case Law::Equal: return "equal spheres, radius " + short_number(a_);
    case Law::Uniform: return "uniform" + range;
    case Law::Lognormal:
      return "lognormal, median " + short_number(a_) + ", sigma of ln r " + short_number(b_) + " (cut at " +
             short_number(kTruncateSigmas) + " sigma)" + range;
    case Law::Normal:
      return "normal, mean " + short_number(a_) + ", std " + short_number(b_) + " (cut at " +
             short_number(kTruncateSigmas) + " sigma" +
             (Impl::t_lo(*this) > -kTruncateSigmas ? ", none below " + g3(100 * kFloorShare) + "% of the mean" : "") +
             ")" + range;
    case Law::Discrete: {
      std::string out = "discrete, " + std::to_string(radii_.size()) + " radii by " + to_string(basis_) + ":";
      const std::vector<SizeClass> classes = size_classes();
      for (size_t i = 0; i < classes.size() && i < 8; ++i) {
        const double share = basis_ == FractionBasis::Volume ? classes[i].volume_share : classes[i].number_share;
        out += (i ? ", " : " ") + g3(radii_[i]) + " (" + g3(100 * share) + "%)";
      }
      if (classes.size() > 8) out += ", ... (" + std::to_string(classes.size() - 8) + " more)";
      return out;
    }
    case Law::Sieve:
      return "sieve curve " + excerpt(trim_spaces(spec_), 60) + ", " + std::to_string(size_classes().size()) +
             " classes by volume" + range;
  }
  return "";
}

double RadiusDistribution::min_radius() const {
  if (law_ == Law::Equal) return a_;
  if (law_ == Law::Discrete) return radii_.front();
  if (law_ == Law::Sieve) {
    const std::vector<double> w = Impl::sieve_numbers(*this);
    size_t i = 0;
    while (i + 1 < w.size() && !(w[i] > 0)) ++i;
    return radii_[i == 0 ? 0 : i - 1];
  }
  return Impl::r_of(*this, Impl::t_lo(*this));
}

double RadiusDistribution::max_radius() const {
  if (law_ == Law::Equal) return a_;
  if (law_ == Law::Discrete) return radii_.back();
  if (law_ == Law::Sieve) {
    const std::vector<double> w = Impl::sieve_numbers(*this);
    size_t i = w.size() - 1;
    while (i > 0 && !(w[i] > 0)) --i;
    return radii_[i];
  }
  return Impl::r_of(*this, Impl::t_hi(*this));
}

double RadiusDistribution::mean() const {
  return Impl::expect(*this, [](double r) { return r; });
}

double RadiusDistribution::stddev() const {
  const double m = mean();
  return std::sqrt(Impl::expect(*this, [m](double r) { return (r - m) * (r - m); }));
}

double RadiusDistribution::skewness() const {
  const double m = mean(), s = stddev();
  if (!(s > 1e-12 * m)) return 0;  // one radius: no shape
  return Impl::expect(*this, [m](double r) { return (r - m) * (r - m) * (r - m); }) / (s * s * s);
}

double RadiusDistribution::mean_cube() const {
  return Impl::expect(*this, [](double r) { return r * r * r; });
}

double RadiusDistribution::rcp_gain() const {
  if (is_equal()) return 0;
  const double d = stddev() / mean();
  return 0.0658 * d + 0.0857 * skewness() * d * d;
}

double RadiusDistribution::cdf(double r) const {
  switch (law_) {
    case Law::Equal: return r >= a_ ? 1 : 0;
    case Law::Discrete: {
      double sum = 0;
      for (size_t i = 0; i < radii_.size() && radii_[i] <= r; ++i) sum += shares_[i];
      return std::min(sum, 1.0);
    }
    case Law::Sieve: {
      const std::vector<double> w = Impl::sieve_numbers(*this);
      if (r < radii_[0]) return 0;
      double sum = w[0];
      for (size_t i = 1; i < w.size(); ++i) {
        if (r >= radii_[i]) {
          sum += w[i];
        } else {
          sum += w[i] * Impl::within(radii_[i - 1], radii_[i], r);
          break;
        }
      }
      return std::min(sum, 1.0);
    }
    default: return Impl::cdf_t(*this, Impl::t_of(*this, r));
  }
}

double RadiusDistribution::quantile(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  switch (law_) {
    case Law::Equal: return a_;
    case Law::Discrete: {
      double sum = 0;  // summed as cdf() sums, so quantile(cdf(R)) == R
      for (size_t i = 0; i < radii_.size(); ++i) {
        sum += shares_[i];
        if (u <= sum) return radii_[i];
      }
      return radii_.back();
    }
    case Law::Sieve: {
      const std::vector<double> w = Impl::sieve_numbers(*this);
      if (w[0] > 0 && u <= w[0]) return radii_[0];
      double sum = w[0];
      for (size_t i = 1; i < w.size(); ++i) {
        if (w[i] > 0 && u <= sum + w[i])
          return Impl::within_inverse(radii_[i - 1], radii_[i], std::clamp((u - sum) / w[i], 0.0, 1.0));
        sum += w[i];
      }
      return max_radius();
    }
    default: return Impl::r_of(*this, Impl::t_of_u(*this, u));
  }
}

std::vector<SizeClass> RadiusDistribution::size_classes(int bins) const {
  std::vector<SizeClass> out;
  auto volumes = [&out] {  // volume shares from the number shares and the classes' mean r^3
    double total = 0;
    for (const SizeClass& c : out) total += c.volume_share;
    for (SizeClass& c : out) c.volume_share /= total;
  };
  if (law_ == Law::Equal) return {SizeClass{a_, a_, 1, 1}};
  if (law_ == Law::Discrete) {
    for (size_t i = 0; i < radii_.size(); ++i)
      out.push_back({radii_[i], radii_[i], shares_[i], shares_[i] * std::pow(radii_[i] / radii_.back(), 3)});
    volumes();
    return out;
  }
  if (law_ == Law::Sieve) {
    const std::vector<double> w = Impl::sieve_numbers(*this);
    if (w[0] > 0) out.push_back({radii_[0], radii_[0], w[0], shares_[0]});
    for (size_t i = 1; i < w.size(); ++i)  // intervals of no share are left out: never drawn
      if (w[i] > 0) out.push_back({radii_[i - 1], radii_[i], w[i], shares_[i] - shares_[i - 1]});
    return out;
  }
  bins = std::max(bins, 1);
  const double s = max_radius();
  double t = Impl::t_lo(*this);
  for (int k = 0; k < bins; ++k) {
    const double next = k + 1 == bins ? Impl::t_hi(*this) : Impl::t_of_u(*this, double(k + 1) / bins);
    const double v = Impl::integrate(*this, t, next, [s](double r) { return std::pow(r / s, 3); });
    out.push_back({Impl::r_of(*this, t), Impl::r_of(*this, next), 1.0 / bins, v});
    t = next;
  }
  volumes();
  return out;
}

double RadiusDistribution::draw_in_class(const std::vector<SizeClass>& classes, size_t k, double u) const {
  if (k >= classes.size())
    throw Error("radii: size class " + std::to_string(k) + " asked of " + std::to_string(classes.size()));
  const SizeClass& c = classes[k];
  if (c.lo == c.hi) return c.lo;
  // The law inside [lo, hi]; cdf(lo) holds a sieve's share at its smallest radius, so it is skipped.
  const double f0 = cdf(c.lo), f1 = cdf(c.hi);
  return std::clamp(quantile(f0 + std::clamp(u, 0.0, 1.0) * (f1 - f0)), c.lo, c.hi);
}


}  // namespace pfill
