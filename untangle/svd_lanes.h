// Symmetric 3 x 3 eigensystems (cyclic Jacobi) and the signed SVD of 3 x 3 matrices, one
// matrix per vector lane, for the hex corner-tet lane kernels (untangle/tet_energy_lanes.cpp).
#pragma once

#include <utility>

#include "hexmesh/core/types.h"
#include "untangle/lanes.h"
#include "untangle/signed_svd.h"

namespace hexmesh::untangle {

// The largest |a_ij| of a symmetric 3 x 3 matrix (upper triangle) in every lane; NaN where an
// entry is NaN or infinite, so that range tests on it fail there.
HEXMESH_LANE_INLINE Lanes largest_entry(const Lanes (&a)[3][3]) {
    Lanes largest = lane_abs(a[0][0]), sum = a[0][0];
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) largest = lane_max(largest, lane_abs(a[i][j])), sum += a[i][j];
    return largest + 0 * sum;
}

// Scales the symmetric matrix a (upper triangle) by 1 / largest_entry in the lanes where that
// lies in [1e-280, 1e280] (returned: its reciprocal or 1, and `usable`), and replaces it by the
// identity in the others (zero, out of range, not finite), whose results the caller discards.
HEXMESH_LANE_INLINE Lanes normalize_lanes(Lanes (&a)[3][3], LaneInts& usable) {
    const Lanes largest = largest_entry(a);
    usable = (largest >= 1e-280) & (largest <= 1e280);
    const Lanes one = largest * 0 + 1, scale = usable ? 1 / largest : one;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) a[i][j] = usable ? a[i][j] * scale : (i == j ? one : 0 * one);
    return scale;
}

// Cyclic Jacobi rotations on the symmetric 3 x 3 matrix a (upper triangle used) in every
// lane, until every lane's off-diagonal part is below 1e-17 of its largest |a_ii| (at most
// 12 sweeps): a's diagonal becomes its eigenvalues and v (set here) the eigenvectors, as
// columns. No trigonometry, no branch per lane. Its entries must be at most about 1 in
// magnitude (normalize_lanes), so that their squares do not overflow.
HEXMESH_LANE_INLINE void jacobi_lanes(Lanes (&a)[3][3], Lanes (&v)[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) v[i][j] = a[0][0] * 0 + (i == j ? 1 : 0);
    for (int sweep = 0; sweep < 12; ++sweep) {
        const Lanes size =
            lane_max(lane_max(lane_abs(a[0][0]), lane_abs(a[1][1])), lane_abs(a[2][2]));
        const Lanes off = lane_abs(a[0][1]) + lane_abs(a[0][2]) + lane_abs(a[1][2]);
        if (!any_lane(off > 1e-17 * size)) break;
        for (const auto& [p, q] : {std::pair{0, 1}, {0, 2}, {1, 2}}) {
            const int r = 3 - p - q;
            const Lanes apq = a[p][q], d = a[q][q] - a[p][p];
            // t = tan of the angle that zeroes a_pq: 2 a_pq sgn(d) / (|d| + sqrt(d^2 + 4 a_pq^2)).
            const Lanes denominator = lane_abs(d) + lane_sqrt(d * d + 4 * apq * apq);
            const Lanes t =
                denominator > 0 ? 2 * apq / (d < 0 ? -denominator : denominator) : d * 0;
            const Lanes c = 1 / lane_sqrt(1 + t * t), sn = t * c;
            a[p][p] -= t * apq;
            a[q][q] += t * apq;
            a[p][q] = d * 0;
            Lanes& arp = p < r ? a[p][r] : a[r][p];
            Lanes& arq = q < r ? a[q][r] : a[r][q];
            const Lanes rp = arp, rq = arq;
            arp = c * rp - sn * rq;
            arq = sn * rp + c * rq;
            for (int k = 0; k < 3; ++k) {
                const Lanes vp = v[k][p], vq = v[k][q];
                v[k][p] = c * vp - sn * vq;
                v[k][q] = sn * vp + c * vq;
            }
        }
    }
}

// signed_svd in every lane, the eigensystem of S^T S by jacobi_lanes: V its eigenvectors
// sorted by decreasing eigenvalue and turned into a rotation; U by Gram-Schmidt on S V as in
// signed_svd; sigma the diagonal of U^T S V. s[3 k + c] = S(c, k). Lanes whose S^T S is zero,
// not finite or out of range (largest entry outside [1e-280, 1e280]) take the scalar
// signed_svd.
HEXMESH_LANE_INLINE void signed_svd_lanes(const Lanes (&s)[9], Lanes (&u)[3][3], Lanes (&sigma)[3],
                                          Lanes (&v)[3][3]) {
    // A = S^T S, scaled by its largest entry (the eigenvectors do not change).
    Lanes a[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            a[i][j] =
                s[3 * i] * s[3 * j] + s[3 * i + 1] * s[3 * j + 1] + s[3 * i + 2] * s[3 * j + 2];
    LaneInts usable;
    normalize_lanes(a, usable);
    jacobi_lanes(a, v);
    // Eigenvalues largest first: compare-and-swap (0, 1), (0, 2), (1, 2), columns of V with them.
    Lanes lambda[3] = {a[0][0], a[1][1], a[2][2]};
    for (const auto& [i, j] : {std::pair{0, 1}, {0, 2}, {1, 2}}) {
        const LaneInts swap = lambda[i] < lambda[j];
        const Lanes li = lambda[i];
        lambda[i] = swap ? lambda[j] : li;
        lambda[j] = swap ? li : lambda[j];
        for (int k = 0; k < 3; ++k) {
            const Lanes vi = v[k][i];
            v[k][i] = swap ? v[k][j] : vi;
            v[k][j] = swap ? vi : v[k][j];
        }
    }
    const Lanes det_v = v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1]) -
                        v[0][1] * (v[1][0] * v[2][2] - v[1][2] * v[2][0]) +
                        v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]);
    for (int k = 0; k < 3; ++k) v[k][2] = det_v < 0 ? -v[k][2] : v[k][2];
    // S V, then U: u0 = unit(sv0), u1 = unit(sv1 - (u0 . sv1) u0), u2 = u0 x u1.
    Lanes sv[3][3];  // sv[k][r] = (S V)(r, k)
    for (int k = 0; k < 3; ++k)
        for (int r = 0; r < 3; ++r)
            sv[k][r] = s[r] * v[0][k] + s[3 + r] * v[1][k] + s[6 + r] * v[2][k];
    const Lanes zero{}, one = zero + 1;
    const Lanes n0 = lane_sqrt(sv[0][0] * sv[0][0] + sv[0][1] * sv[0][1] + sv[0][2] * sv[0][2]);
    const LaneInts has0 = n0 > 1e-300;
    Lanes u0[3];
    for (int r = 0; r < 3; ++r) u0[r] = has0 ? sv[0][r] / n0 : (r == 0 ? one : zero);
    // A unit vector orthogonal to u0 (like Eigen's unitOrthogonal: in the xy-plane unless u0 is
    // nearly along z).
    const LaneInts along_z = (u0[0] * u0[0] + u0[1] * u0[1]) <= 1e-24 * (u0[2] * u0[2]);
    const Lanes nxy = lane_sqrt(u0[0] * u0[0] + u0[1] * u0[1]),
                nyz = lane_sqrt(u0[1] * u0[1] + u0[2] * u0[2]);
    const Lanes normal[3] = {along_z ? zero : -u0[1] / nxy, along_z ? -u0[2] / nyz : u0[0] / nxy,
                             along_z ? u0[1] / nyz : zero};
    const Lanes dot01 = u0[0] * sv[1][0] + u0[1] * sv[1][1] + u0[2] * sv[1][2];
    Lanes w1[3];
    for (int r = 0; r < 3; ++r) w1[r] = sv[1][r] - dot01 * u0[r];
    const Lanes n1 = lane_sqrt(w1[0] * w1[0] + w1[1] * w1[1] + w1[2] * w1[2]);
    const LaneInts has1 = n1 > 1e-300;
    Lanes u1[3];
    for (int r = 0; r < 3; ++r) u1[r] = has1 ? w1[r] / n1 : normal[r];
    const Lanes u2[3] = {u0[1] * u1[2] - u0[2] * u1[1], u0[2] * u1[0] - u0[0] * u1[2],
                         u0[0] * u1[1] - u0[1] * u1[0]};
    for (int r = 0; r < 3; ++r) u[r][0] = u0[r], u[r][1] = u1[r], u[r][2] = u2[r];
    for (int k = 0; k < 3; ++k)
        sigma[k] = u[0][k] * sv[k][0] + u[1][k] * sv[k][1] + u[2][k] * sv[k][2];
    if (!any_lane(~usable)) return;
    for (int l = 0; l < lane_count; ++l) {
        if (usable[l]) continue;
        Mat3 sl, ul, vl;
        Vec3 sigma_l;
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) sl(c, k) = s[3 * k + c][l];
        signed_svd(sl, ul, sigma_l, vl);
        for (int r = 0; r < 3; ++r) {
            sigma[r][l] = sigma_l[r];
            for (int c = 0; c < 3; ++c) u[r][c][l] = ul(r, c), v[r][c][l] = vl(r, c);
        }
    }
}

}  // namespace hexmesh::untangle
