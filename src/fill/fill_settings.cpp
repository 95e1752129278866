// The table of a fill's settings (fill_settings.hpp): names, tiers, help,
// and the parsers that turn text into FillOptions fields.
#include "pfill/fill_settings.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>

#include "pfill/error.hpp"
#include "fill/short_number.hpp"

namespace pfill {
namespace {

/// Error messages quote at most this much of a value.
std::string quoted(const std::string& text) {
  return "'" + excerpt(text, 40) + "'";
}

/// A finite number, the whole text.
double real_of(const std::string& name, const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (text.empty() || end != begin + text.size() || !std::isfinite(v))
    throw Error(name + " " + quoted(text) + " is not a finite number");
  return v;
}

/// A whole number in [lo, hi], the whole text.
long long whole_of(const std::string& name, const std::string& text, long long lo, long long hi) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(begin, &end, 10);
  if (text.empty() || end != begin + text.size())
    throw Error(name + " " + quoted(text) + " is not a whole number");
  if (errno == ERANGE || v < lo || v > hi)
    throw Error(name + " " + quoted(text) + " is out of range: give " + std::to_string(lo) + ".." + std::to_string(hi));
  return v;
}

/// `n` finite numbers separated by commas.
std::vector<double> reals_of(const std::string& name, const std::string& text, size_t n, const char* form) {
  std::vector<double> out;
  size_t start = 0;
  for (;;) {
    const size_t comma = text.find(',', start);
    const std::string part = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    try {
      out.push_back(real_of(name, part));
    } catch (const Error&) {
      throw Error(name + " " + quoted(text) + ": give " + form);
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (out.size() != n) throw Error(name + " " + quoted(text) + ": give " + form);
  return out;
}

/// `positive`: only numbers above 0 (for a setting whose 0 means "not given").
template <class T>
FillSetting real(const char* name, T FillOptions::*field, SettingTier tier, const char* help, bool positive = false) {
  return {name, "", tier, "NUMBER", help,
          [=](FillOptions& o, const std::string& t) {
            const double v = real_of(name, t);
            if (positive && !(v > 0)) throw Error(std::string(name) + " " + quoted(t) + " must be a positive number");
            o.*field = static_cast<T>(v);
          },
          [=](const FillOptions& o) { return short_number(static_cast<double>(o.*field)); }};
}

template <class T>
FillSetting whole(const char* name, T FillOptions::*field, SettingTier tier, long long lo, const char* help) {
  const long long hi = static_cast<long long>(std::min<unsigned long long>(
      std::numeric_limits<T>::max(), static_cast<unsigned long long>(std::numeric_limits<long long>::max())));
  return {name, "", tier, "N", help,
          [=](FillOptions& o, const std::string& t) { o.*field = static_cast<T>(whole_of(name, t, lo, hi)); },
          [=](const FillOptions& o) { return std::to_string(o.*field); }};
}

FillSetting stop_setting(const char* name, StopCriterion FillOptions::*field, SettingTier tier, const char* help) {
  return {name, "", tier, "blocked|ke|collisions", help,
          [=](FillOptions& o, const std::string& t) { o.*field = parse_stop_criterion(t); },
          [=](const FillOptions& o) { return std::string(to_string(o.*field)); }};
}

FillSetting colour_setting(const char* name, std::optional<ColourOptions> FillOptions::*field, SettingTier tier,
                           const char* help) {
  return {name, "", tier, "surface|depth|none|#RRGGBB", help,
          [=](FillOptions& o, const std::string& t) { o.*field = parse_colour_option(t); },
          [=](const FillOptions& o) { return o.*field ? colour_mode_name((o.*field)->mode) : std::string(); }};
}

FillSetting text_setting(const char* name, std::string FillOptions::*field, SettingTier tier, const char* form,
                         const char* help) {
  return {name, "", tier, form, help, [=](FillOptions& o, const std::string& t) { o.*field = t; },
          [=](const FillOptions& o) { return o.*field; }};
}

// The basis (radii_by) is applied when the fill plans (fill_sizes), so the
// order of the two on a command line or in Python's keywords does not matter.
FillSetting radii_setting(const char* name, SettingTier tier, const char* help) {
  return {name, "", tier, "SPEC", help,
          [](FillOptions& o, const std::string& t) { o.radii = RadiusDistribution::parse(t, o.radii_by); },
          [](const FillOptions& o) { return o.radii ? o.radii->spec() : std::string(); }};
}

FillSetting radii_by_setting(const char* name, SettingTier tier, const char* help) {
  return {name, "", tier, "number|volume", help,
          [](FillOptions& o, const std::string& t) { o.radii_by = parse_fraction_basis(t); },
          [](const FillOptions& o) { return std::string(to_string(o.radii_by)); }};
}

FillSetting point_setting(const char* name, std::optional<Vec3> FillOptions::*field, SettingTier tier,
                          const char* help) {
  return {name, "", tier, "X,Y,Z", help,
          [=](FillOptions& o, const std::string& t) {
            const std::vector<double> v = reals_of(name, t, 3, "three numbers X,Y,Z");
            o.*field = Vec3(v[0], v[1], v[2]);
          },
          [=](const FillOptions& o) {
            const std::optional<Vec3>& p = o.*field;
            return p ? short_number(p->x) + "," + short_number(p->y) + "," + short_number(p->z) : std::string();
          }};
}

FillSetting pair(const char* name, std::array<double, 2> FillOptions::*field, SettingTier tier, const char* form,
                 const char* help) {
  return {name, "", tier, form, help,
          [=](FillOptions& o, const std::string& t) {
            const std::vector<double> v = reals_of(name, t, 2, form);
            o.*field = {v[0], v[1]};
          },
          [=](const FillOptions& o) { return short_number((o.*field)[0]) + "," + short_number((o.*field)[1]); }};
}

/// A setting whose 0 means "not given" (count, radius): shown as unset.
FillSetting with_short(FillSetting s, const char* short_flag) {
  s.short_flag = short_flag;
  const auto get = s.get;
  s.get = [get](const FillOptions& o) {
    const std::string v = get(o);
    return v == "0" ? std::string() : v;
  };
  return s;
}

// The setting's name is its field's: one name from C++ through Python to the flag.
#define FIELD(f) #f, &FillOptions::f

/// What a user chooses: `pfill fill --help`.
std::vector<FillSetting> user_settings() {
  using T = SettingTier;
  return {
      with_short(whole(FIELD(count), T::User, 1,
                       "About this many particles (picks the radius, allowing for rest_distance); default 4000"),
                 "-n"),
      with_short(real(FIELD(radius), T::User, "Particle radius in mesh units (instead of a count)", true),
                 "-r"),
      radii_setting("radii", T::User,
                    "Unequal spheres: uniform:MIN,MAX | lognormal:MEDIAN,SIGMA (sigma of ln r) | normal:MEAN,STD "
                    "(both cut at 3 sigma) | discrete:R1:F1,R2:F2,... | FILE.csv (radius, cumulative volume "
                    "fraction); discrete fractions by number (--radii-by volume: by volume), a CSV's by volume; with -n "
                    "the radii are relative"),
      radii_by_setting("radii_by", T::Tuning, "What discrete:... fractions are: number (default) or volume"),
      real(FIELD(max_overlap), T::User,
           "Largest overlap of any pair after the fill, a fraction of r (of the smaller radius) (0: none)"),
      real(FIELD(rest_distance), T::User,
           "Rest distance of the potential in contact distances 2r (>= 1; larger: sparser)"),
      real(FIELD(epsilon), T::User, "Depth of the potential well"),
      pair(FIELD(exponents), T::User, "A,B", "The potential's exponents A > B > 0 (repulsive, attractive)"),
      real(FIELD(cutoff), T::User, "Cutoff in sigma (e.g. 2.5) for the attractive form; 0: purely repulsive"),
      real(FIELD(restitution), T::User, "Particle-particle restitution, 0..1"),
      real(FIELD(wall_restitution), T::User, "Particle-surface restitution, 0..1"),
      stop_setting(FIELD(stop), T::User,
                   "What ends pass 1: blocked (the birth sites are full), or the report's ke (kinetic energy) or "
                   "collisions tests (the finish then compresses what they leave)"),
      whole(FIELD(seed), T::User, 0, "Random seed (same seed, mesh, options and device: same particles)"),
      colour_setting(FIELD(colour), T::User,
                     "Particle colours: surface (the mesh's colours or texture), depth, none or #RRGGBB (default: "
                     "surface when the mesh has colours, else none)"),
      text_setting(FIELD(device), T::User, "INDEX|NAME",
                   "OpenCL device: index or name (see `pfill devices`; or PFILL_DEVICE)"),
  };
}

/// Tuning of the births (pass 1), in --help-all.
std::vector<FillSetting> birth_settings() {
  using T = SettingTier;
  return {
      whole(FIELD(sites), T::Tuning, -1,
            "Birth sites: -1 automatic (waves from about 2,000 particles on, else 2 sites); 0 births in waves "
            "over sites spread inside; N the deepest point, then far deep points (the report's schedule)"),
      real(FIELD(site_depth), T::Tuning,
           "sites >= 1: sites after the first lie at least this share of the deepest point's depth inside"),
      real(FIELD(site_spacing), T::Tuning, "Waves: sites at least this many rest distances apart"),
      real(FIELD(site_min_depth), T::Tuning, "Waves: sites at least this many radii inside"),
      real(FIELD(room_spacing), T::Tuning,
           "Waves: until half the count is in, births also at room sites this many rest distances apart, where "
           "a newborn overlaps nothing (0: none)"),
      whole(FIELD(birth_every), T::Tuning, 0,
            "Steps between birth attempts at each site (0: automatic, 0.48 tau for waves, 3 at the report's "
            "sites)"),
      point_setting(FIELD(birth), T::Tuning, "First birth site (must lie a radius inside; default the deepest point)"),
      pair(FIELD(birth_speed), T::Tuning, "MIN,MAX",
           "Newborn speed range, fractions of the top speed"),
      real(FIELD(birth_clearance), T::Tuning,
           "A site has room when no centre is within this many rest distances (0: automatic, 0.55 for waves, 0.5 "
           "at the report's sites)"),
      whole(FIELD(patience), T::Tuning, 0,
            "Steps with no birth that mean the sites are blocked (0: automatic, 15 tau: 1,500 steps at a step of "
            "0.01 tau)"),
      real(FIELD(stop_share), T::Tuning,
           "Waves: pass 1 also ends when the births of the last `patience` steps are at most this share of the "
           "particles (-1: automatic, 0.03 under a max_overlap below 0.01, else 0.003)"),
      real(FIELD(max_overfill), T::Tuning,
           "Waves of equal spheres under a max_overlap below 0.01: pass 1 also ends when the particles are this "
           "share over the expected count (-1: never)"),
      whole(FIELD(max_steps), T::Tuning, 0,
            "Step budget of pass 1 (0: automatic, 100 a particle + 20,000); when it runs out, pass 1 ends with "
            "what is in"),
  };
}

/// Tuning of the dynamics, the finish and the machinery, in --help-all.
std::vector<FillSetting> other_tuning_settings() {
  using T = SettingTier;
  return {
      // ---- tuning: dynamics ----
      real(FIELD(damping), T::Tuning, "Velocity damping rate during passes 1 and 2"),
      real(FIELD(time_step), T::Tuning,
           "Time step of pass 1 and the settle in units of the potential's time scale tau (0: automatic, 0.02 for "
           "waves of equal spheres, else 0.01)"),
      real(FIELD(max_step), T::Tuning,
           "Top speed: the most a particle moves in a step, in sigma (0: automatic, 10 time_step)"),
      whole(FIELD(settle_steps), T::Tuning, 1, "Most steps of the settle (it ends sooner at rest)"),
      // ---- tuning: the finish ----
      whole(FIELD(hole_rounds), T::Tuning, 0,
            "Rounds of inserting spheres into empty pockets in the finish (0: none)"),
      real(FIELD(hole_clearance), T::Tuning,
           "A pocket takes a sphere when the nearest centre is this many rest distances away"),
      real(FIELD(containment_tolerance), T::Tuning,
           "Allowed crossing of the surface, a fraction of r"),
      // ---- tuning: machinery ----
      real(FIELD(field_spacing), T::Tuning, "Distance field spacing, in radii"),
      real(FIELD(skin), T::Tuning, "Neighbour-list skin in sigma (0: automatic, on CPUs 0.9 while repulsive spheres are born, else 0.5; 0.3 on GPUs)"),
      whole(FIELD(sync_every), T::Tuning, 1,
            "Steps between reads of the step history and positions (the report's schedule)"),
      whole(FIELD(sort_every), T::Tuning, 0,
            "Steps between renumberings of the particles along the cells (0: never)"),
  };
}

std::vector<FillSetting> make_table() {
  std::vector<FillSetting> t = user_settings();
  for (auto part : {birth_settings(), other_tuning_settings()}) t.insert(t.end(), part.begin(), part.end());
  return t;
}

#undef FIELD

}  // namespace

std::string FillSetting::flag() const {
  std::string f = "--" + name;
  for (char& c : f)
    if (c == '_') c = '-';
  return f;
}

const std::vector<FillSetting>& fill_settings() {
  static const std::vector<FillSetting> table = make_table();
  return table;
}

const FillSetting* find_fill_setting(const std::string& name) {
  for (const FillSetting& s : fill_settings())
    if (s.name == name) return &s;
  return nullptr;
}

std::string with_flags(const std::string& message) {
  // Names of two words and more (rest_distance) wherever they stand; names
  // that are also plain words (radius, count, stop) only as the message's
  // first word, its subject. Longest first: `birth_speed` before `birth`.
  std::vector<const FillSetting*> by_length;
  for (const FillSetting& s : fill_settings()) by_length.push_back(&s);
  std::sort(by_length.begin(), by_length.end(),
            [](const FillSetting* a, const FillSetting* b) { return a->name.size() > b->name.size(); });
  auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; };
  std::string out;
  for (size_t i = 0; i < message.size();) {
    bool replaced = false;
    if (i == 0 || !word_char(message[i - 1]))
      for (const FillSetting* s : by_length) {
        const size_t n = s->name.size();
        if (message.compare(i, n, s->name) != 0 || (i + n < message.size() && word_char(message[i + n]))) continue;
        if (i > 0 && s->name.find('_') == std::string::npos) continue;
        out += s->flag();
        i += n;
        replaced = true;
        break;
      }
    if (!replaced) out += message[i++];
  }
  return out;
}

}  // namespace pfill
