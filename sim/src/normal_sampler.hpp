// Internal: standard normal samples from std::mt19937_64 by the Box-Muller transform. Written out
// here because std::normal_distribution differs between standard libraries, and a seed must give
// the same scan everywhere.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace iilfm::sim {

class NormalSampler {
 public:
  explicit NormalSampler(std::uint64_t seed) : engine_(seed) {}

  double next() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    constexpr double kTwoPi = 6.283185307179586;
    const double u1 = 1.0 - uniform();  // (0, 1]: log stays finite
    const double u2 = uniform();
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_ = radius * std::sin(kTwoPi * u2);
    has_spare_ = true;
    return radius * std::cos(kTwoPi * u2);
  }

 private:
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }  // [0, 1)

  std::mt19937_64 engine_;
  double spare_ = 0;
  bool has_spare_ = false;
};

// Uniform numbers in [0, 1) from their own std::mt19937_64 stream, for the optional effects
// (dropouts, invalid points), so switching those on leaves every beam's noise unchanged.
class UniformSampler {
 public:
  explicit UniformSampler(std::uint64_t seed) : engine_(seed ^ 0x9e3779b97f4a7c15ull) {}
  double next() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

 private:
  std::mt19937_64 engine_;
};

}  // namespace iilfm::sim
