// The signed SVD of a 3 x 3 matrix from the closed-form eigensystem of S^T S.
#include "untangle/signed_svd.h"

#include <Eigen/Eigenvalues>

namespace hexmesh::untangle {

void signed_svd(const Mat3& s, Mat3& u, Vec3& sigma, Mat3& v) {
    Eigen::SelfAdjointEigenSolver<Mat3> eigen;
    eigen.computeDirect(s.transpose() * s);
    v = eigen.eigenvectors().rowwise().reverse();  // eigenvalues ascend: largest first
    if (v.determinant() < 0) v.col(2) *= -1;
    const Mat3 sv = s * v;
    auto unit_or = [](const Vec3& w, const Vec3& fallback) {
        const double n = w.norm();
        return n > 1e-300 ? Vec3(w / n) : fallback;
    };
    u.col(0) = unit_or(sv.col(0), Vec3::UnitX());
    const Vec3 any_normal = u.col(0).unitOrthogonal();
    u.col(1) = unit_or(sv.col(1) - u.col(0).dot(sv.col(1)) * u.col(0), any_normal);
    u.col(2) = u.col(0).cross(u.col(1));
    for (int k = 0; k < 3; ++k) sigma[k] = u.col(k).dot(sv.col(k));
}

}  // namespace hexmesh::untangle
