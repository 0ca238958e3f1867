// The sums behind fit_rigid (Kabsch), kept apart so that a caller perturbing one target point can
// update them in constant time instead of summing every pair again (rigid_fit_covariance).
#pragma once

#include <vector>

#include "iilfm/types.hpp"

namespace iilfm::detail {

struct RigidFitSums {
  Vec3 mean_source = Vec3::Zero(), mean_target = Vec3::Zero();  // weighted means
  // sum of w (target - mean_target) (source - mean_source)^T. As sum of w (source - mean_source)
  // is zero, moving target k by e changes it by w_k e (source_k - mean_source)^T alone.
  Mat3 cross = Mat3::Zero();
  double spread = 0;  // sum of w |source - mean_source|^2
  double total = 0;   // sum of the weights
  bool ok = false;    // false: fewer than 3 pairs, sizes that differ, a negative or NaN weight
};

RigidFitSums rigid_fit_sums(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                            const std::vector<double>& weights);

// The proper rotation and translation best mapping source onto target for these sums; false when
// the source points are (nearly) collinear or coincident.
bool rigid_transform_of(const RigidFitSums& sums, Isometry3& T);

}  // namespace iilfm::detail
