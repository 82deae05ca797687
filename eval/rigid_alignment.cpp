#include "eval/rigid_alignment.h"

#include <Eigen/SVD>
#include <cmath>
#include <string>

#include "core/error.h"

namespace sb {
namespace {

// Throws when the centred points do not span at least a plane.
void checkSpread(const Eigen::Matrix3Xd& centred, const char* name) {
  const Eigen::Index n = centred.cols();
  if (!centred.allFinite()) {
    throw Error(std::string("alignment: the ") + name +
                " positions contain non-finite values; fix the input");
  }
  // Singular values of the centred 3xN points are the spreads along the principal directions (m * sqrt(N)).
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  const double s0 = sv(0), s1 = sv(1);
  const double rmsSpread = s0 / std::sqrt(static_cast<double>(n));
  if (rmsSpread <= kIdenticalSpreadM) {
    throw Error(std::string("alignment undefined: all ") + std::to_string(n) + " matched " + name +
                " positions are identical (the camera did not move); ATE needs positions spanning a plane");
  }
  if (s1 <= kCollinearRelativeTolerance * s0) {
    throw Error(std::string("alignment undefined: the ") + std::to_string(n) + " matched " + name +
                " positions are collinear, so the rotation about that line is free; ATE needs positions "
                "spanning a plane (use a longer or non-straight trajectory)");
  }
}

}  // namespace

Eigen::Isometry3d alignRigid(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to, const char* fromName,
                             const char* toName) {
  if (from.cols() != to.cols()) {
    throw Error("alignment: " + std::to_string(from.cols()) + " " + fromName + " points but " +
                std::to_string(to.cols()) + " " + toName + " points; they must correspond one to one");
  }
  if (from.cols() < 3) {
    throw Error("alignment: only " + std::to_string(from.cols()) + " point pairs; at least 3 are needed");
  }
  const Eigen::Vector3d fromMean = from.rowwise().mean();
  const Eigen::Vector3d toMean = to.rowwise().mean();
  const Eigen::Matrix3Xd fromC = from.colwise() - fromMean;
  const Eigen::Matrix3Xd toC = to.colwise() - toMean;
  checkSpread(fromC, fromName);
  checkSpread(toC, toName);

  // Cross-covariance to * from^T = U S V^T; R = U diag(1, 1, d) V^T with d = sign(det(U V^T)).
  const Eigen::Matrix3d cov = toC * fromC.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d sv = svd.singularValues();
  if (sv(1) <= kCollinearRelativeTolerance * sv(0)) {
    throw Error(std::string("alignment undefined: the ") + fromName + " and " + toName +
                " positions vary along directions that do not correlate (cross-covariance of rank < 2), "
                "so the rotation is not determined; check that the trajectories belong together");
  }
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) d(2, 2) = -1.0;
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = svd.matrixU() * d * svd.matrixV().transpose();
  out.translation() = toMean - out.linear() * fromMean;
  return out;
}

}  // namespace sb
