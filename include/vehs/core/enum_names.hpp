#pragma once
// Enum <-> string conversion from one table per enum (Ceres style), so that configs, help
// texts and outputs all spell an option the same way.
#include <array>
#include <string>
#include <string_view>
#include <utility>

#include "vehs/core/error.hpp"

namespace vehs {

template <class Enum, std::size_t N>
using EnumNames = std::array<std::pair<Enum, std::string_view>, N>;

template <class Enum, std::size_t N>
std::string enum_to_string(const EnumNames<Enum, N>& table, Enum value) {
  for (const auto& [e, name] : table)
    if (e == value) return std::string(name);
  return "unknown";
}

/// All names of a table joined as "a, b, c" (for help texts and error messages).
template <class Enum, std::size_t N>
std::string enum_choices(const EnumNames<Enum, N>& table) {
  std::string out;
  for (const auto& [e, name] : table) {
    if (!out.empty()) out += ", ";
    out += name;
  }
  return out;
}

/// Parses `text`; on failure throws Error("<what> must be one of ...").
template <class Enum, std::size_t N>
Enum enum_from_string(const EnumNames<Enum, N>& table, std::string_view text,
                      const std::string& what) {
  for (const auto& [e, name] : table)
    if (name == text) return e;
  throw Error(what + " must be one of " + enum_choices(table) + " (got '" + std::string(text) +
              "')");
}

}  // namespace vehs
