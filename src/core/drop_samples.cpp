#include "vehs/core/drop_samples.hpp"

#include <algorithm>

namespace vehs {

Dataset drop_samples(const Dataset& data, const std::vector<SampleRef>& removed, std::size_t min_samples) {
  Dataset out;
  auto copy = [](const auto& from, auto& to, std::size_t a, std::size_t b) {
    to.insert(to.end(), from.begin() + static_cast<std::ptrdiff_t>(a), from.begin() + static_cast<std::ptrdiff_t>(b));
  };
  auto piece = [&](const Record& rec, std::size_t from, std::size_t to) {  // samples [from, to)
    if (to <= from || to - from < std::max<std::size_t>(min_samples, 2)) return;
    Record r = rec;
    r.offset = out.x.size();
    r.size = to - from;
    r.first_line = rec.first_line + from;
    r.t0 = rec.t0 + static_cast<double>(from) * rec.dt;
    copy(data.x, out.x, rec.offset + from, rec.offset + to);
    if (data.has_u()) copy(data.u, out.u, rec.offset + from, rec.offset + to);
    if (data.has_y()) copy(data.y, out.y, rec.offset + from, rec.offset + to);
    out.records.push_back(r);
  };
  std::size_t g = 0;
  for (std::size_t k = 0; k < data.records.size(); ++k) {
    std::size_t from = 0;
    for (; g < removed.size() && removed[g].record == k; ++g) {
      piece(data.records[k], from, removed[g].sample);
      from = removed[g].sample + 1;
    }
    piece(data.records[k], from, data.records[k].size);
  }
  return out;
}

}  // namespace vehs
