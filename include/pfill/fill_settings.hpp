/// @file fill_settings.hpp
/// @brief Every setting of a fill under one name, in one table: the
/// FillOptions field, the keyword of Python's pfill.fill() and, with dashes,
/// the command-line flag (`max_overlap`: --max-overlap). The command line
/// and Python build their options from it, parse values with it and show
/// its help, so the three never drift apart. Tier User is what `pfill fill
/// --help` shows; Tuning changes how a fill gets there (`--help-all`).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "pfill/fill.hpp"

namespace pfill {

enum class SettingTier { User, Tuning };

struct FillSetting {
  std::string name;        ///< the field, the Python keyword; the flag with '-' for '_'
  std::string short_flag;  ///< e.g. "-n"; empty for none
  SettingTier tier = SettingTier::Tuning;
  std::string value_form;  ///< what a value looks like: NUMBER, N, A,B, X,Y,Z, or the choices
  std::string help;        ///< one sentence
  /// Sets the field from text (a number, "A,B", "X,Y,Z", a name); throws
  /// pfill::Error naming the setting when the text is not of its form.
  /// Ranges are checked when the fill starts (check_fill_options).
  std::function<void(FillOptions&, const std::string&)> set;
  /// The field's value as text, in the form `set` reads ("" when unset).
  std::function<std::string(const FillOptions&)> get;

  /// "--max-overlap" for "max_overlap".
  std::string flag() const;
};

/// The table, users' settings first.
const std::vector<FillSetting>& fill_settings();

/// The setting named `name` (a Python keyword or a flag without dashes), or
/// nullptr.
const FillSetting* find_fill_setting(const std::string& name);

/// Throws pfill::Error with one line naming the first setting of `o` out of
/// its range (fill() checks too: callers need this only to fail before
/// reading a mesh). src/fill/fill_options_check.cpp
void check_fill_options(const FillOptions& o);

/// `message` with each setting's name replaced by its flag: the library's
/// errors name settings, the command line shows them as the user typed them.
std::string with_flags(const std::string& message);

}  // namespace pfill
