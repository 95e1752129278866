// The table of a fill's settings (fill_settings.hpp): one name per
// setting, values parsed and written back alike, bad text refused with the
// setting's name, and the command line's flags put in for the names.
#include <doctest/doctest.h>

#include <set>

#include "pfill/error.hpp"
#include "pfill/fill_settings.hpp"

using namespace pfill;

namespace {

std::string error_of(const FillSetting& s, const std::string& text) {
  FillOptions o;
  try {
    s.set(o, text);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("every setting has one name, a flag made of it, help, and its default reads back as set") {
  std::set<std::string> names;
  for (const FillSetting& s : fill_settings()) {
    CAPTURE(s.name);
    CHECK(names.insert(s.name).second);
    CHECK(s.flag().rfind("--", 0) == 0);
    CHECK(s.flag().find('_') == std::string::npos);
    CHECK(!s.help.empty());
    CHECK(find_fill_setting(s.name) == &s);
    const FillOptions defaults;
    const std::string text = s.get(defaults);
    if (text.empty()) continue;  // unset by default (count, radius, birth, colour, device)
    FillOptions o;
    s.set(o, text);
    CHECK(s.get(o) == text);
  }
  CHECK(find_fill_setting("no_such_setting") == nullptr);
  // The user's tier is what `pfill fill --help` lists: short enough to read.
  size_t users = 0;
  for (const FillSetting& s : fill_settings()) users += s.tier == SettingTier::User;
  CHECK(users <= 15);  // (14, and radii; radii_by is tuning)
}

TEST_CASE("settings parse into their fields") {
  FillOptions o;
  find_fill_setting("exponents")->set(o, "10,4");
  CHECK(o.exponents[0] == 10);
  CHECK(o.exponents[1] == 4);
  find_fill_setting("birth")->set(o, "1,-2,3.5");
  REQUIRE(o.birth);
  CHECK(o.birth->z == 3.5);
  find_fill_setting("count")->set(o, "1000");
  CHECK(o.count == 1000);
  find_fill_setting("stop")->set(o, "ke");
  CHECK(o.stop == StopCriterion::KineticEnergy);
  find_fill_setting("hole_rounds")->set(o, "7");
  CHECK(o.hole_rounds == 7);
  find_fill_setting("sites")->set(o, "-1");
  CHECK(o.sites == -1);
}

TEST_CASE("text that is not of a setting's form is refused, naming the setting") {
  for (const FillSetting& s : fill_settings()) {
    if (s.name == "device") continue;  // any text names a device (its choice fails later, naming it)
    CAPTURE(s.name);
    for (const char* bad : {"", "nan", "inf", "-inf", "abc", "1e999"}) {
      CAPTURE(bad);
      const std::string e = error_of(s, bad);
      CHECK(!e.empty());
      CHECK(e.find(s.name) != std::string::npos);
      CHECK(e.find('\n') == std::string::npos);
      CHECK(e.size() < 300);
    }
  }
  CHECK(!error_of(*find_fill_setting("count"), "1.5").empty());
  CHECK(!error_of(*find_fill_setting("count"), "0").empty());
  CHECK(!error_of(*find_fill_setting("radius"), "0").empty());
  CHECK(!error_of(*find_fill_setting("radius"), "-1").empty());
  CHECK(!error_of(*find_fill_setting("seed"), "-1").empty());
  CHECK(!error_of(*find_fill_setting("exponents"), "12").empty());
  CHECK(!error_of(*find_fill_setting("birth"), "1,2").empty());
  CHECK(error_of(*find_fill_setting("count"), std::string(100000, '9')).size() < 300);  // long values are cut
}

TEST_CASE("the command line's flags stand in for the names in the library's messages") {
  CHECK(with_flags("rest_distance must be 1..10") == "--rest-distance must be 1..10");
  CHECK(with_flags("radius must be a positive number") == "--radius must be a positive number");
  CHECK(with_flags("patience must be at least 100 steps and 10 birth intervals (birth_every)") ==
        "--patience must be at least 100 steps and 10 birth intervals (--birth-every)");
  CHECK(with_flags("birth_speed 'x': give MIN,MAX") == "--birth-speed 'x': give MIN,MAX");
  // Names that are plain words stay words away from the start.
  CHECK(with_flags("no particle of radius 0.1 fits; ask for a larger count") ==
        "no particle of radius 0.1 fits; ask for a larger count");
}
