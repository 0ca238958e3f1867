// Uncertainty of rigid poses fitted to lifted corners: the corners' joint covariance (plane fit and
// in-plane detection error) carried through the fit to a 6x6 pose covariance.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "iilfm/lift.hpp"
#include "iilfm/types.hpp"

namespace iilfm {

using Mat6 = Eigen::Matrix<double, 6, 6>;

// Pose covariances are 6x6 over (rx, ry, rz, x, y, z): rotation as a right perturbation in the
// pose's own (child) frame, R_true = R_est Exp([rx ry rz]), radians; then the translation (the
// child frame's origin in the parent frame), metres. For T_world_lidar that is the LiDAR's axes
// and its position in the world; for T_lidar_marker the marker's axes (rx, ry tilt its face, rz
// turns it in its plane) and its centre in the LiDAR frame.

// Joint covariance (3n x 3n) of n corners lifted onto `plane`: the plane's offset uncertainty
// moves every corner along its ray, correlated between corners (Plane::offset_covariance); the
// detection's in-plane error moves each independently within the plane, `in_plane_sigma` (metres,
// per in-plane axis).
Eigen::MatrixXd plane_corner_covariance(const std::vector<Vec3>& corners, const Plane& plane,
                                        double in_plane_sigma);

// Joint covariance (3n x 3n) that the pixel grid adds to a polygon's n corners: the detector
// places each edge where the binary image changes class, so each edge sits off its true line by
// a quantisation error shared by both its corners (an in-plane shift or stretch of the whole
// marker, which no per-corner residual can see). `model` holds the corners in the marker frame
// (z = 0), `corners_px` their image positions, T the marker's pose (LiDAR frame). Each edge's
// offset has `sigma_px` pixels along its image normal, divided by the square root of the number
// of pixel phases its rows or columns cross (a slanted edge averages its quantisation; one along
// the grid does not). Empty when the sizes disagree or fewer than 3 corners are given.
Eigen::MatrixXd edge_offset_covariance(const std::vector<Vec3>& model,
                                       const std::vector<Vec2>& corners_px, const Isometry3& T,
                                       double sigma_px);

// Sum of squared in-plane residuals of the best affine map taking the planar model `source`
// (z = 0) onto `target` seen through pose T (target ~ T * source): what is left of the corners'
// scatter once a shrink or growth of the detected square, uniform or not (a threshold's bias on
// a beam footprint taller than wide, which moves no pose), is taken out.
double affine_residual_sq(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                          const Isometry3& T);

// In-plane sigma of a square's corners from `residual_sq` (affine_residual_sq) over its degrees
// of freedom: 2n in-plane residuals minus the affine map's 6. A prior of `prior_sigma` worth
// `prior_dof` residuals keeps a lucky near-zero residual (and 4 corners leave only 2 degrees of
// freedom) from claiming precision it cannot have.
double in_plane_sigma(double residual_sq, std::size_t corners, double prior_sigma,
                      double prior_dof = 2);

// Covariance (convention above) of fit_rigid(source, target, weights).T, or of its inverse when
// `inverse`, given the targets' joint covariance (3n x 3n): the fit's Jacobian by central
// differences, then J C J^T. Zero matrix when the fit fails.
Mat6 rigid_fit_covariance(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                          const std::vector<double>& weights, const Eigen::MatrixXd& target_cov,
                          bool inverse);

// Standard deviations of the translation (metres) and of roll, pitch, yaw (degrees, as rpy_deg)
// of pose T with covariance C.
Vec3 translation_std(const Mat6& C);
Vec3 rpy_std_deg(const Isometry3& T, const Mat6& C);

}  // namespace iilfm
