#include "surface/implicit_features.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "surface/projection.h"

namespace hexmesh {

namespace {

using Piece = ImplicitFunction::Piece;

constexpr double window_factor = 4;        // pieces sought within this * length_scale
constexpr double max_step_factor = 8;      // a step moves at most this * length_scale
constexpr double target_residual = 1e-12;  // relative to length_scale
constexpr int max_iterations = 50;
constexpr int max_halvings = 30;

double min_sine() {
    static const double s = std::sin(same_normal_degrees * std::acos(-1.0) / 180);
    return s;
}

// Up to `wanted` (<= 3) pieces with distinct normals, nearest to zero first: the second off
// the line of the first, the third off the plane of the first two.
struct Selection {
    int count = 0;
    Piece pieces[3];
    Vec3 normals[3];  // unit
};

Selection select_pieces(std::vector<Piece>& candidates, int wanted) {
    std::stable_sort(candidates.begin(), candidates.end(), [](const Piece& a, const Piece& b) {
        return std::abs(a.value) < std::abs(b.value);
    });
    Selection s;
    Vec3 crease = Vec3::Zero();  // unit n_0 x n_1 once two are chosen
    for (const Piece& piece : candidates) {
        if (s.count == wanted) break;
        const double gn = piece.gradient.norm();
        if (!std::isfinite(piece.value) || !std::isfinite(gn) || !(gn > 0)) continue;
        const Vec3 n = piece.gradient / gn;
        if (s.count == 1) {
            const Vec3 c = s.normals[0].cross(n);
            if (c.norm() <= min_sine()) continue;
            crease = c.normalized();
        } else if (s.count == 2 && std::abs(n.dot(crease)) <= min_sine()) {
            continue;
        }
        s.pieces[s.count] = piece;
        s.normals[s.count] = n;
        ++s.count;
    }
    return s;
}

Selection active_selection(const ImplicitFunction& u, const Vec3& p, double tolerance, int wanted) {
    std::vector<Piece> pieces;
    u.active_pieces(p, tolerance, pieces);
    return select_pieces(pieces, wanted);
}

// The larger |value| of the k selected pieces, +inf if fewer than k were found.
double residual(const Selection& s, int k) {
    if (s.count < k) return std::numeric_limits<double>::infinity();
    double r = 0;
    for (int i = 0; i < k; ++i) r = std::max(r, std::abs(s.pieces[i].value));
    return r;
}

// Minimum-norm step to where the linear models of the k pieces vanish: -J^T (J J^T)^-1 g.
Vec3 least_norm_step(const Selection& s, int k) {
    Eigen::Matrix<double, Eigen::Dynamic, 3, 0, 3, 3> jacobian(k, 3);
    Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> values(k);
    for (int i = 0; i < k; ++i) {
        jacobian.row(i) = s.pieces[i].gradient.transpose();
        values[i] = s.pieces[i].value;
    }
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3> gram =
        jacobian * jacobian.transpose();
    return -jacobian.transpose() * gram.ldlt().solve(values);
}

// Newton / Gauss-Newton onto the common zero of k = 2 or 3 pieces, re-selected at each
// point; the start point's selection must have k pieces.
Vec3 solve_on_pieces(const ImplicitFunction& u, const Vec3& p, double length_scale, int k,
                     Selection current) {
    const double window = window_factor * length_scale;
    const double max_step = max_step_factor * length_scale;
    Vec3 x = p;
    double r = residual(current, k);
    for (int it = 0; it < max_iterations && r >= target_residual * length_scale; ++it) {
        Vec3 step = least_norm_step(current, k);
        const double length = step.norm();
        if (!std::isfinite(length)) break;
        if (length > max_step) step *= max_step / length;
        bool moved = false;
        for (int h = 0; h < max_halvings && !moved; ++h, step *= 0.5) {
            const Selection trial = active_selection(u, x + step, window, k);
            const double trial_r = residual(trial, k);
            if (trial_r < r) {
                x += step;
                current = trial;
                r = trial_r;
                moved = true;
            }
        }
        if (!moved) break;
    }
    return x;
}

void require_positive_length(double length_scale, const char* who) {
    if (!(length_scale > 0) || !std::isfinite(length_scale))
        throw std::invalid_argument(std::string(who) + ": length_scale must be positive, got " +
                                    std::to_string(length_scale));
}

}  // namespace

FeatureKind classify_surface_point(const ImplicitFunction& u, const Vec3& p, double tolerance) {
    switch (active_selection(u, p, tolerance, 3).count) {
        case 0:
        case 1:
            return FeatureKind::smooth;
        case 2:
            return FeatureKind::crease;
        default:
            return FeatureKind::corner;
    }
}

Vec3 crease_tangent(const ImplicitFunction& u, const Vec3& p, double tolerance) {
    const Selection s = active_selection(u, p, tolerance, 2);
    if (s.count < 2) return Vec3::Zero();
    return s.normals[0].cross(s.normals[1]).normalized();
}

Vec3 project_to_crease(const ImplicitFunction& u, const Vec3& p, double length_scale) {
    require_positive_length(length_scale, "project_to_crease");
    const Selection start = active_selection(u, p, window_factor * length_scale, 2);
    if (start.count < 2) return project_to_surface(u, p, length_scale).point;
    return solve_on_pieces(u, p, length_scale, 2, start);
}

Vec3 snap_to_corner(const ImplicitFunction& u, const Vec3& p, double length_scale) {
    require_positive_length(length_scale, "snap_to_corner");
    const Selection start = active_selection(u, p, window_factor * length_scale, 3);
    if (start.count < 3) return project_to_crease(u, p, length_scale);
    return solve_on_pieces(u, p, length_scale, 3, start);
}

}  // namespace hexmesh
