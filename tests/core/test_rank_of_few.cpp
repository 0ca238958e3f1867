// value_of_rank_among_few selects what std::nth_element selects, on either side of kFewValues.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "../../src/rank_of_few.hpp"

namespace iilfm::detail {
namespace {

float nth(std::vector<float> v, std::size_t k) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

void expect_every_rank(const std::vector<float>& values, const char* what) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    std::vector<float> copy = values;
    EXPECT_EQ(value_of_rank_among_few(copy.data(), copy.size(), k), nth(values, k))
        << what << ", n " << values.size() << ", rank " << k;
    if (values.size() <= kFewValues) {
      EXPECT_EQ(copy, values) << "reordered " << what;
    }
  }
}

TEST(RankOfFew, EveryRankOfRandomValuesWithTiesAsNthElement) {
  std::mt19937 rng(7);
  for (const std::size_t n : {1, 2, 3, 7, 80, 191, 192, 193, 250}) {
    // Whole intensities, as a LiDAR reports them: many ties.
    std::uniform_int_distribution<int> level(0, 40);
    std::vector<float> tied(n), spread(n);
    for (float& v : tied) v = static_cast<float>(level(rng));
    std::normal_distribution<float> noise(100.0f, 30.0f);
    for (float& v : spread) v = noise(rng);
    expect_every_rank(tied, "tied");
    expect_every_rank(spread, "spread");
  }
}

TEST(RankOfFew, SortedReversedAndEqualValues) {
  std::vector<float> up(150), equal(150, 3.5f);
  for (std::size_t i = 0; i < up.size(); ++i) up[i] = static_cast<float>(i) - 20.0f;
  std::vector<float> down(up.rbegin(), up.rend());
  expect_every_rank(up, "sorted");
  expect_every_rank(down, "reversed");
  expect_every_rank(equal, "equal");
  const std::vector<float> extremes = {std::numeric_limits<float>::infinity(),  -0.0f, 0.0f,
                                       -std::numeric_limits<float>::infinity(), 1e30f, -1e-30f};
  expect_every_rank(extremes, "infinities and signed zeros");
}

}  // namespace
}  // namespace iilfm::detail
