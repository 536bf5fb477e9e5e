#pragma once
// Internal (src/io/csv_reader.cpp; tested directly): ISO-8601 time stamps in a time column, as loggers write them —
// "2026-11-25T07:00:00.125", "2026-11-25 07:00:00,125", with an optional "Z" or ±hh:mm offset.
// They become seconds since the file's first stamp (exact to the digits given: the whole seconds
// are counted as integers, so 10⁻⁶ s steps at an epoch of 1.8·10⁹ s keep their spacing).
#include <optional>
#include <string_view>

namespace vehs::io_detail {

/// A stamp's whole seconds since 1970-01-01 UTC and its fraction of a second, or nothing when
/// `text` is not an ISO-8601 date and time (or names an impossible date or time).
struct IsoTime {
  long long seconds = 0;
  double fraction = 0.0;
};
std::optional<IsoTime> parse_iso8601(std::string_view text);

}  // namespace vehs::io_detail
