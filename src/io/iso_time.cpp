#include "vehs/io/detail/iso_time.hpp"

#include <cctype>

namespace vehs::io_detail {

namespace {

/// Days from 1970-01-01 to y-m-d in the proleptic Gregorian calendar (H. Hinnant's
/// days_from_civil).
long long days_from_civil(long long y, unsigned m, unsigned d) {
  y -= m <= 2;
  const long long era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long long>(doe) - 719468;
}

bool leap(long long y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

unsigned days_in_month(long long y, unsigned m) {
  static const unsigned d[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && leap(y) ? 29 : d[m - 1];
}

/// `n` digits at `p` as a number; false when not all are digits.
bool digits(std::string_view s, std::size_t p, std::size_t n, unsigned& out) {
  if (p + n > s.size()) return false;
  out = 0;
  for (std::size_t i = p; i < p + n; ++i) {
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
    out = out * 10 + static_cast<unsigned>(s[i] - '0');
  }
  return true;
}

}  // namespace

std::optional<IsoTime> parse_iso8601(std::string_view s) {
  unsigned Y, M, D, h, m, sec;
  if (s.size() < 19 || s[4] != '-' || s[7] != '-' || (s[10] != 'T' && s[10] != ' ') || s[13] != ':' || s[16] != ':')
    return std::nullopt;
  if (!digits(s, 0, 4, Y) || !digits(s, 5, 2, M) || !digits(s, 8, 2, D) || !digits(s, 11, 2, h) ||
      !digits(s, 14, 2, m) || !digits(s, 17, 2, sec))
    return std::nullopt;
  if (M < 1 || M > 12 || D < 1 || D > days_in_month(Y, M) || h > 23 || m > 59 || sec > 60) return std::nullopt;
  std::size_t p = 19;
  double fraction = 0.0;
  if (p < s.size() && (s[p] == '.' || s[p] == ',')) {
    double scale = 0.1;
    std::size_t q = p + 1;
    for (; q < s.size() && std::isdigit(static_cast<unsigned char>(s[q])); ++q, scale *= 0.1)
      fraction += scale * (s[q] - '0');
    if (q == p + 1) return std::nullopt;
    p = q;
  }
  long long offset = 0;  // seconds east of UTC
  if (p < s.size() && s[p] == 'Z') {
    ++p;
  } else if (p < s.size() && (s[p] == '+' || s[p] == '-')) {
    unsigned oh, om = 0;
    if (!digits(s, p + 1, 2, oh)) return std::nullopt;
    std::size_t q = p + 3;
    if (q < s.size() && s[q] == ':') ++q;
    if (q < s.size() && !digits(s, q, 2, om)) return std::nullopt;
    if (q < s.size()) q += 2;
    if (oh > 23 || om > 59) return std::nullopt;
    offset = (s[p] == '+' ? 1 : -1) * static_cast<long long>(oh * 3600 + om * 60);
    p = q;
  }
  if (p != s.size()) return std::nullopt;
  IsoTime t;
  t.seconds = days_from_civil(Y, M, D) * 86400 + h * 3600 + m * 60 + sec - offset;
  t.fraction = fraction;
  return t;
}

}  // namespace vehs::io_detail
