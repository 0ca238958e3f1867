// Gauss-Newton refinement of the LiDAR pose on corner rays and marker-plane points
// (lidar_pose.hpp, docs/pipeline.md).
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "iilfm/lidar_pose.hpp"

namespace iilfm {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;

// 99.9 % points of the chi-square distribution with 3 and 6 degrees of freedom.
constexpr double kChi2Plane = 16.27;
constexpr double kChi2Pose = 22.46;

Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// The map's plane n.x = d through a marker's world corners; nullopt when they are collinear.
struct WorldPlane {
  Vec3 normal;
  double d;
};

std::optional<WorldPlane> world_plane(const std::vector<Vec3>& world) {
  if (world.size() < 3) return std::nullopt;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : world) centre += p / static_cast<double>(world.size());
  Mat3 scatter = Mat3::Zero();
  for (const Vec3& p : world) scatter += (p - centre) * (p - centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(scatter);
  if (!(eig.eigenvalues()(1) > 1e-12 * eig.eigenvalues()(2))) return std::nullopt;
  const Vec3 normal = eig.eigenvectors().col(0);
  return WorldPlane{normal, normal.dot(centre)};
}

// Whitening for a covariance: W with W^T W = C^-1 (W = L^-1 for C = L L^T); nullopt when C is
// not positive definite.
template <int N>
std::optional<Eigen::Matrix<double, N, N>> whitening(const Eigen::Matrix<double, N, N>& C) {
  const Eigen::LLT<Eigen::Matrix<double, N, N>> llt(C);
  if (llt.info() != Eigen::Success) return std::nullopt;
  using M = Eigen::Matrix<double, N, N>;
  return M(llt.matrixL().solve(M::Identity()));
}

// One marker's residuals, whitened, prepared once: residual and Jacobian at any pose follow from
// the pose alone.
struct CornerTerm {
  Vec3 world, lidar;
  Eigen::Matrix<double, Eigen::Dynamic, 3> project;  // whitened projection (2x3 or 3x3)
};

struct PlaneTerm {
  std::size_t marker = 0;
  WorldPlane map;
  Vec3 centre, axis1, axis2;
  double offset_sigma = 0, slope1_sigma = 0, slope2_sigma = 0;
  bool active = true;
};

struct Problem {
  std::vector<CornerTerm> corners;
  std::vector<PlaneTerm> planes;
};

// Sigma for corners without a known covariance: the start pose's residual over its 3n - 6
// degrees of freedom, as the Kabsch covariance takes it.
double residual_sigma(const std::vector<MarkerCorrespondence>& markers, const Isometry3& start) {
  const Isometry3 T_lidar_world = start.inverse();
  double sum_sq = 0;
  std::size_t n = 0;
  for (const MarkerCorrespondence& m : markers) {
    for (std::size_t k = 0; k < m.world.size(); ++k) {
      sum_sq += (T_lidar_world * m.world[k] - m.lidar[k]).squaredNorm();
      ++n;
    }
  }
  return std::sqrt(sum_sq / std::max(1.0, 3.0 * static_cast<double>(n) - 6));
}

bool usable_plane(const MarkerCorrespondence& m) {
  const auto& p = m.plane;
  return p && p->ok && p->offset_variance > 0 && p->slope_variance.minCoeff() > 0;
}

Problem make_problem(const std::vector<MarkerCorrespondence>& markers, const Isometry3& start) {
  Problem problem;
  const double fallback_sigma = std::max(residual_sigma(markers, start), 1e-6);
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const MarkerCorrespondence& m = markers[i];
    const bool known = m.lidar_covariance.rows() == static_cast<Eigen::Index>(3 * m.lidar.size());
    const bool planar = usable_plane(m);
    for (std::size_t k = 0; k < m.world.size(); ++k) {
      const Mat3 C = known ? Mat3(m.lidar_covariance.block<3, 3>(3 * k, 3 * k))
                           : Mat3(Mat3::Identity() * fallback_sigma * fallback_sigma);
      CornerTerm term{m.world[k], m.lidar[k], {}};
      const Vec3 ray = m.lidar[k].normalized();
      if (planar && std::abs(m.plane->normal.dot(ray)) > 1e-3) {
        // Along the ray onto the plane, in the plane's axes: what the plane's error cannot move.
        const Vec3& n = m.plane->normal;
        const Mat3 along_ray = Mat3::Identity() - ray * n.transpose() / n.dot(ray);
        Eigen::Matrix<double, 2, 3> E;
        E.row(0) = m.plane->axis1.transpose();
        E.row(1) = m.plane->axis2.transpose();
        const Eigen::Matrix<double, 2, 3> in_plane = E * along_ray;
        const Eigen::Matrix2d C2 = in_plane * C * in_plane.transpose();
        const auto W = whitening<2>(C2);
        if (!W) continue;
        term.project = *W * in_plane;
      } else {
        const auto W = whitening<3>(C);
        if (!W) continue;
        term.project = *W;
      }
      problem.corners.push_back(std::move(term));
    }
    if (!planar) continue;
    const std::optional<WorldPlane> map = world_plane(m.world);
    if (!map) continue;
    const Plane& p = *m.plane;
    problem.planes.push_back(PlaneTerm{i, *map, p.centre, p.axis1, p.axis2,
                                       std::sqrt(p.offset_variance), std::sqrt(p.slope_variance(0)),
                                       std::sqrt(p.slope_variance(1)), true});
  }
  return problem;
}

// The plane term's whitened residuals (offset at the centre, slope along each axis of the map's
// plane seen from the LiDAR, against the fitted plane) and their Jacobian.
Vec3 plane_residual(const PlaneTerm& t, const Isometry3& T_world_lidar,
                    Eigen::Matrix<double, 3, 6>* J = nullptr) {
  const Mat3 R = T_world_lidar.linear();
  const Vec3 n = R.transpose() * t.map.normal;
  const double d = t.map.d - t.map.normal.dot(T_world_lidar.translation());
  const Vec3 r(n.dot(t.centre) - d, n.dot(t.axis1), n.dot(t.axis2));
  const Vec3 scale(1 / t.offset_sigma, 1 / t.slope1_sigma, 1 / t.slope2_sigma);
  if (J) {
    // n' = n + n x w for a right rotation by w; d' = d - n_world . dt.
    J->setZero();
    J->block<1, 3>(0, 0) = t.centre.cross(n).transpose();
    J->block<1, 3>(0, 3) = t.map.normal.transpose();
    J->block<1, 3>(1, 0) = t.axis1.cross(n).transpose();
    J->block<1, 3>(2, 0) = t.axis2.cross(n).transpose();
    for (int row = 0; row < 3; ++row) J->row(row) *= scale(row);
  }
  return r.cwiseProduct(scale);
}

struct Normal {
  Mat6 H = Mat6::Zero();
  Vec6 g = Vec6::Zero();
  double cost = 0;
  int residuals = 0;
};

Normal normal_equations(const Problem& problem, const Isometry3& T_world_lidar) {
  Normal eq;
  const Mat3 Rt = T_world_lidar.linear().transpose();
  const Isometry3 T_lidar_world = T_world_lidar.inverse();
  for (const CornerTerm& c : problem.corners) {
    const Vec3 predicted = T_lidar_world * c.world;
    // x' = x + x skew(w)... : d x / d w = [x]x, d x / d t = -R^T.
    Eigen::Matrix<double, 3, 6> Jx;
    Jx.leftCols<3>() = skew(predicted);
    Jx.rightCols<3>() = -Rt;
    const Eigen::VectorXd r = c.project * (predicted - c.lidar);
    const Eigen::MatrixXd J = c.project * Jx;
    eq.H += J.transpose() * J;
    eq.g += J.transpose() * r;
    eq.cost += r.squaredNorm();
    eq.residuals += static_cast<int>(r.size());
  }
  for (const PlaneTerm& t : problem.planes) {
    if (!t.active) continue;
    Eigen::Matrix<double, 3, 6> J;
    const Vec3 r = plane_residual(t, T_world_lidar, &J);
    eq.H += J.transpose() * J;
    eq.g += J.transpose() * r;
    eq.cost += r.squaredNorm();
    eq.residuals += 3;
  }
  return eq;
}

Isometry3 moved(const Isometry3& T, const Vec6& step) {
  Isometry3 out = T;
  const double angle = step.head<3>().norm();
  if (angle > 0)
    out.linear() = T.linear() * Eigen::AngleAxisd(angle, step.head<3>() / angle).toRotationMatrix();
  out.translation() += step.tail<3>();
  return out;
}

Vec6 difference(const Isometry3& from, const Isometry3& to) {
  Vec6 x;
  const Eigen::AngleAxisd aa(Mat3(from.linear().transpose() * to.linear()));
  x.head<3>() = aa.angle() * aa.axis();
  x.tail<3>() = to.translation() - from.translation();
  return x;
}

// Gauss-Newton from `start`; a step that raises the cost is halved (the problem is nearly linear
// near the Kabsch pose, so this rarely happens).
bool solve(const Problem& problem, const Isometry3& start, Isometry3& T, Normal& eq) {
  T = start;
  eq = normal_equations(problem, T);
  for (int it = 0; it < 20; ++it) {
    const Eigen::LDLT<Mat6> ldlt(eq.H);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return false;
    Vec6 step = -ldlt.solve(eq.g);
    bool improved = false;
    for (int halving = 0; halving < 8 && !improved; ++halving, step /= 2) {
      const Isometry3 candidate = moved(T, step);
      const Normal next = normal_equations(problem, candidate);
      if (next.cost <= eq.cost) {
        T = candidate;
        eq = next;
        improved = true;
      }
    }
    if (!improved || step.norm() < 1e-12) break;
  }
  const Eigen::LDLT<Mat6> ldlt(eq.H);
  return ldlt.info() == Eigen::Success && ldlt.vectorD().minCoeff() > 0;
}

}  // namespace

PoseRefinement refine_lidar_pose(const std::vector<MarkerCorrespondence>& markers,
                                 const Isometry3& start, const Mat6& start_covariance) {
  PoseRefinement out;
  Problem problem = make_problem(markers, start);
  const Eigen::LDLT<Mat6> start_ldlt(start_covariance);
  const bool gate_on_start =
      start_ldlt.info() == Eigen::Success && start_ldlt.vectorD().minCoeff() > 0;
  while (true) {
    const auto active = std::count_if(problem.planes.begin(), problem.planes.end(),
                                      [](const PlaneTerm& t) { return t.active; });
    if (active == 0) {  // the corners alone: the start pose already is their fit
      for (const PlaneTerm& t : problem.planes)
        out.planes_rejected.push_back(markers[t.marker].key);
      return out;
    }
    Isometry3 T;
    Normal eq;
    if (!solve(problem, start, T, eq)) return out;
    // The worst plane, and whether the pose stays where the corners allow.
    double worst_chi2 = -1;
    PlaneTerm* worst = nullptr;
    for (PlaneTerm& t : problem.planes) {
      if (!t.active) continue;
      const double chi2 = plane_residual(t, T).squaredNorm();
      if (chi2 > worst_chi2) {
        worst_chi2 = chi2;
        worst = &t;
      }
    }
    const Vec6 pulled = difference(start, T);
    const bool within_start = !gate_on_start || pulled.dot(start_ldlt.solve(pulled)) <= kChi2Pose;
    if (worst_chi2 > kChi2Plane || !within_start) {
      worst->active = false;
      continue;
    }
    out.ok = true;
    out.T_world_lidar = T;
    out.chi2 = eq.cost;
    out.dof = eq.residuals - 6;
    // The inverse normal matrix holds when the terms' variances are right; residuals larger than
    // they claim (chi-square over its degrees of freedom above 1) scale it up, never down.
    const double variance_factor = out.dof > 0 ? std::max(1.0, out.chi2 / out.dof) : 1.0;
    const Mat6 covariance = eq.H.ldlt().solve(Mat6::Identity()) * variance_factor;
    out.covariance = (covariance + covariance.transpose()) / 2;
    for (const PlaneTerm& t : problem.planes)
      (t.active ? out.planes_used : out.planes_rejected).push_back(markers[t.marker].key);
    return out;
  }
}

}  // namespace iilfm
