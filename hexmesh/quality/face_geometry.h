// Private to hexmesh/quality: OpenFOAM's face and cell geometry and its face quality measures.
//
// Each function follows the OpenFOAM routine named in its comment (primitiveMeshTools,
// OpenFOAM-dev and ESI agree on these), with the same guards (ROOTVSMALL, VSMALL), so that
// the numbers match what checkMesh prints for the same polyMesh.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

#include "hexmesh/core/types.h"

namespace hexmesh::detail {

inline constexpr double foam_vsmall = 1.0e-300;
inline constexpr double foam_rootvsmall = 1.0e-150;
inline constexpr double foam_small = 1.0e-15;  // OpenFOAM's SMALL

struct FaceGeometry {
    Vec3 centre = Vec3::Zero();
    Vec3 area = Vec3::Zero();  // area vector, right-hand normal of the point order
};

// makeFaceCentresAndAreas for a quad: triangles (p_i, p_i+1, point average), centre as the
// area-weighted mean of the triangle centres, area vector as half the sum of their normals.
inline FaceGeometry quad_geometry(const std::array<Vec3, 4>& p) {
    Vec3 f_centre = p[0];
    for (int i = 1; i < 4; ++i) f_centre += p[i];
    f_centre /= 4;

    Vec3 sum_n = Vec3::Zero(), sum_ac = Vec3::Zero();
    double sum_a = 0;
    for (int i = 0; i < 4; ++i) {
        const Vec3& this_point = p[i];
        const Vec3& next_point = p[(i + 1) % 4];
        const Vec3 c = this_point + next_point + f_centre;
        const Vec3 n = (next_point - this_point).cross(f_centre - this_point);
        const double a = n.norm();
        sum_n += n;
        sum_a += a;
        sum_ac += a * c;
    }
    if (sum_a < foam_rootvsmall) return {f_centre, Vec3::Zero()};
    return {(1.0 / 3.0) * sum_ac / sum_a, 0.5 * sum_n};
}

struct CellGeometry {
    Vec3 centre = Vec3::Zero();
    double volume = 0;
};

// makeCellCentresAndVols for one cell, faces given with outward area vectors: pyramids from
// each face to the mean of the face centres.
inline CellGeometry cell_geometry(const std::array<FaceGeometry, 6>& faces) {
    Vec3 c_est = Vec3::Zero();
    for (const FaceGeometry& f : faces) c_est += f.centre;
    c_est /= 6;

    CellGeometry cell;
    for (const FaceGeometry& f : faces) {
        const double pyr3_vol = f.area.dot(f.centre - c_est);
        const Vec3 pc = (3.0 / 4.0) * f.centre + (1.0 / 4.0) * c_est;
        cell.centre += pyr3_vol * pc;
        cell.volume += pyr3_vol;
    }
    if (std::abs(cell.volume) > foam_vsmall)
        cell.centre /= cell.volume;
    else
        cell.centre = c_est;
    cell.volume *= 1.0 / 3.0;
    return cell;
}

// cellClosedness's aspect ratio of a 3D cell: the larger of the ratio of the largest to the
// smallest component of sum |area components|, and 1/6 sum of them over V^(2/3).
inline double cell_aspect_ratio(const std::array<FaceGeometry, 6>& faces, double volume) {
    Vec3 sum_mag = Vec3::Zero();
    for (const FaceGeometry& f : faces) sum_mag += f.area.cwiseAbs();
    const double ratio = sum_mag.maxCoeff() / (sum_mag.minCoeff() + foam_rootvsmall);
    const double v = std::max(foam_rootvsmall, volume);
    return std::max(ratio, 1.0 / 6.0 * sum_mag.sum() / std::pow(v, 2.0 / 3.0));
}

// faceOrthogonality: cosine of the angle between the owner-to-neighbour vector and the area.
inline double face_orthogonality(const Vec3& own_cc, const Vec3& nei_cc, const Vec3& s) {
    const Vec3 d = nei_cc - own_cc;
    return d.dot(s) / (d.norm() * s.norm() + foam_rootvsmall);
}

// Shared tail of faceSkewness and boundaryFaceSkewness: |sv| over the normalisation distance.
inline double skewness_from(const std::array<Vec3, 4>& p, const FaceGeometry& f, const Vec3& cpf,
                            const Vec3& d, double fd) {
    const Vec3 sv = cpf - (f.area.dot(cpf) / (f.area.dot(d) + foam_rootvsmall)) * d;
    const Vec3 sv_hat = sv / (sv.norm() + foam_rootvsmall);
    for (const Vec3& q : p) fd = std::max(fd, std::abs(sv_hat.dot(q - f.centre)));
    return sv.norm() / fd;
}

// faceSkewness of an internal face: distance from the face centre to the owner-neighbour
// line, over max(0.2 |d|, extent of the face along that offset).
inline double face_skewness(const std::array<Vec3, 4>& p, const FaceGeometry& f, const Vec3& own_cc,
                            const Vec3& nei_cc) {
    const Vec3 d = nei_cc - own_cc;
    return skewness_from(p, f, f.centre - own_cc, d, 0.2 * d.norm() + foam_rootvsmall);
}

// boundaryFaceSkewness: as if mirrored across the face, d is Cpf projected on the normal and
// the floor is 0.4 |d| (|d| is half the owner-to-mirror distance).
inline double boundary_face_skewness(const std::array<Vec3, 4>& p, const FaceGeometry& f,
                                     const Vec3& own_cc) {
    const Vec3 cpf = f.centre - own_cc;
    const Vec3 normal = f.area / (f.area.norm() + foam_rootvsmall);
    const Vec3 d = normal * normal.dot(cpf);
    return skewness_from(p, f, cpf, d, 0.4 * d.norm() + foam_rootvsmall);
}

// The 4 of a cell's 8 corner points p listed by `local`.
inline std::array<Vec3, 4> face_of(const std::array<Vec3, 8>& p, const std::array<int, 4>& local) {
    return {p[local[0]], p[local[1]], p[local[2]], p[local[3]]};
}

}  // namespace hexmesh::detail
