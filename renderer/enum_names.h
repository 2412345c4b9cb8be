// Names of enums for command lines, metadata and messages, from one table per enum: the
// table is the only place a name is spelled, so to_string, parsing and the list of choices
// in an error message cannot disagree.
//
// An enum opts in with one declaration next to it, found by argument-dependent lookup:
//
//   inline constexpr EnumName<WorkingSpace> kWorkingSpaceNames[] = {
//       {WorkingSpace::linear_rec709, "linear-rec709"}, {WorkingSpace::acescg, "acescg"}};
//   constexpr std::span<const EnumName<WorkingSpace>> enum_names(WorkingSpace) {
//     return kWorkingSpaceNames;
//   }
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace prism {

template <typename E>
struct EnumName {
  E value;
  const char* name;
};

template <typename E>
concept NamedEnum = requires(E e) {
  { enum_names(e) } -> std::convertible_to<std::span<const EnumName<E>>>;
};

// The value's name; "?" for a value outside the table (a cast from a bad integer).
template <NamedEnum E>
const char* to_string(E value) {
  for (const EnumName<E>& entry : enum_names(E{}))
    if (entry.value == value) return entry.name;
  return "?";
}

// False, leaving *out alone, for a name not in the table.
template <NamedEnum E>
bool parse_enum(std::string_view text, E* out) {
  for (const EnumName<E>& entry : enum_names(E{}))
    if (text == entry.name) {
      *out = entry.value;
      return true;
    }
  return false;
}

// "low, medium or high": the choices, for an error message or a help text.
template <NamedEnum E>
std::string enum_choices(std::string_view last_separator = " or ") {
  const auto names = enum_names(E{});
  std::string text;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) text += i + 1 == names.size() ? last_separator : std::string_view(", ");
    text += names[i].name;
  }
  return text;
}

}  // namespace prism
