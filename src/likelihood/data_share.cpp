#include "vehs/likelihood/detail/data_share.hpp"

#include <algorithm>
#include <cmath>

namespace vehs::likelihood::detail {

Dataset warm_start_share(const Dataset& data, double share, bool keep_records) {
  Dataset out;
  for (const auto& r : data.records) {
    const std::size_t want = std::min(r.size, std::max<std::size_t>(std::size_t(std::ceil(share * double(r.size))), 64));
    const std::size_t pieces = keep_records ? 1 : std::max<std::size_t>(1, std::min<std::size_t>(8, want / 250));
    const std::size_t len = (want + pieces - 1) / pieces;
    for (std::size_t p = 0; p < pieces; ++p) {
      const std::size_t first = pieces == 1 ? 0 : (r.size - len) * p / (pieces - 1);
      const std::size_t n = std::min(len, r.size - first);
      if (n < 2) continue;
      Record rr = r;
      rr.offset = out.x.size();
      rr.size = n;
      rr.first_line = r.first_line + first;
      rr.t0 = r.t0 + double(first) * r.dt;
      out.x.insert(out.x.end(), data.x_of(r) + first, data.x_of(r) + first + n);
      if (data.has_u()) out.u.insert(out.u.end(), data.u_of(r) + first, data.u_of(r) + first + n);
      out.records.push_back(rr);
    }
  }
  return out;
}


}  // namespace vehs::likelihood::detail
