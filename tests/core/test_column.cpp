#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "vehs/core/column.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/core/error.hpp"

namespace {

/// Two records of 3 samples viewing `memory` (x) without a copy.
vehs::Dataset viewing(const std::vector<double>& memory) {
  vehs::Dataset d;
  for (std::size_t i = 0; i < 2; ++i) {
    vehs::Record r;
    r.dt = 0.1;
    r.offset = 3 * i;
    r.size = 3;
    d.records.push_back(r);
  }
  d.x = vehs::Column::view(memory.data(), memory.size());
  return d;
}

}  // namespace

TEST_CASE("a column views caller memory without a copy and reads like an owning one", "[core][column]") {
  const std::vector<double> memory{1.0, 2.0, 3.0, 10.0, 20.0, 30.0};
  const vehs::Dataset d = viewing(memory);
  CHECK(d.x.is_view());
  CHECK(d.x.data() == memory.data());  // the caller's buffer itself
  CHECK(d.x_of(d.records[1]) == memory.data() + 3);
  CHECK(d.total_samples() == 6);
  CHECK_FALSE(d.has_u());
  CHECK(d.x == vehs::Column(memory));  // same values as an owning copy
  const vehs::Dataset copy = d;        // copying a Dataset copies the view, not the values
  CHECK(copy.x.data() == memory.data());
  double sum = 0.0;
  for (double v : d.x) sum += v;
  CHECK(sum == 66.0);
}

TEST_CASE("a viewing column refuses to be modified - own() copies it once", "[core][column]") {
  const std::vector<double> memory{1.0, 2.0, 3.0, 10.0, 20.0, 30.0};
  vehs::Dataset d = viewing(memory);
  CHECK_THROWS_AS(d.x.push_back(1.0), vehs::Error);
  CHECK_THROWS_AS(d.x[0] = 5.0, vehs::Error);
  CHECK_THROWS_WITH(d.x.resize(2), Catch::Contains("read-only"));
  CHECK_THROWS_AS(d.append(viewing(memory)), vehs::Error);  // appending needs an owning dataset
  d.x.own();
  CHECK_FALSE(d.x.is_view());
  CHECK(d.x.data() != memory.data());
  d.x[0] = 5.0;
  CHECK(memory[0] == 1.0);
  vehs::Dataset owning;
  owning.append(viewing(memory));  // an owning dataset appends a view by copying it
  CHECK(owning.x == vehs::Column(memory));
  CHECK(owning.x.data() != memory.data());
}

TEST_CASE("subtract_record_means copies a viewing column and leaves the caller's memory alone", "[core][column]") {
  const std::vector<double> memory{1.0, 2.0, 3.0, 10.0, 20.0, 30.0};
  vehs::Dataset d = viewing(memory);
  vehs::subtract_record_means(d);
  CHECK_FALSE(d.x.is_view());
  CHECK(d.x == vehs::Column({-1.0, 0.0, 1.0, -10.0, 0.0, 10.0}));
  CHECK(memory == std::vector<double>{1.0, 2.0, 3.0, 10.0, 20.0, 30.0});
}

TEST_CASE("the pooled variance of x about each record's own mean", "[core][dataset]") {
  // records {1, 2, 3} and {10, 20, 30}: squares about the means 2 + 200, over 6 − 1 samples
  const std::vector<double> memory{1.0, 2.0, 3.0, 10.0, 20.0, 30.0};
  CHECK(vehs::pooled_record_variance(viewing(memory)) == Approx(202.0 / 5.0));
  vehs::Dataset one;
  one.records.push_back(vehs::Record{});
  one.records[0].size = 1;
  one.x.push_back(4.0);
  CHECK(std::isnan(vehs::pooled_record_variance(one)));
}
