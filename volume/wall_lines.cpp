#include "volume/wall_lines.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "surface/implicit_features.h"

namespace hexmesh {

WallFace block_face(const Block& b, BlockFace face) {
    const int axis = face / 2, p = axis == 0 ? 1 : 0, q = axis == 2 ? 1 : 2;
    return {&b, axis, face % 2 == 1, p, q, b.nodes[p], b.nodes[q], b.nodes[axis]};
}

std::vector<WallFace> wall_faces(const Block& b) {
    std::vector<WallFace> faces;
    for (int f = imin; f <= kmax; ++f)
        if (b.face_patch[f] == "wall" && b.nodes[f / 2] >= 2)
            faces.push_back(block_face(b, BlockFace(f)));
    return faces;
}

std::vector<WallFace> wall_faces(const BlockGrid& grid) {
    std::vector<WallFace> faces;
    for (const Block& b : grid.blocks)
        for (const WallFace& f : wall_faces(b)) faces.push_back(f);
    return faces;
}

double grid_side(const WallFace& f, const std::vector<Vec3>& points, const ImplicitFunction& body) {
    const int t = std::max(1, (f.depth - 1) / 2);
    const Id balance = tbb::parallel_reduce(
        tbb::blocked_range<Id>(0, f.lines()), Id(0),
        [&](const tbb::blocked_range<Id>& r, Id sum) {
            for (Id l = r.begin(); l != r.end(); ++l) {
                const double u = body.value(points[f.node(int(l % f.np), int(l / f.np), t)]);
                sum += (u > 0) - (u < 0);
            }
            return sum;
        },
        [](Id a, Id b) { return a + b; });
    return balance < 0 ? -1.0 : 1.0;
}

void append_wall_normals(const ImplicitFunction& body, const Vec3& x0, double side,
                         double tolerance, std::vector<Vec3>& normals) {
    std::vector<ImplicitFunction::Piece> pieces;
    body.active_pieces(x0, tolerance, pieces);
    const double same = std::cos(same_normal_degrees * 3.14159265358979323846 / 180);
    for (const auto& piece : pieces) {
        if (!(piece.gradient.norm() > 0) || !piece.gradient.allFinite()) continue;
        const Vec3 n = side * piece.gradient.normalized();
        if (std::none_of(normals.begin(), normals.end(),
                         [&](const Vec3& m) { return m.dot(n) > same; }))
            normals.push_back(n);
    }
}

std::optional<Vec3> unit_offset(const ImplicitFunction& body, const Vec3& x0, double side,
                                double tolerance) {
    std::vector<Vec3> normals;
    append_wall_normals(body, x0, side, tolerance, normals);
    if (normals.empty()) return std::nullopt;
    Eigen::MatrixXd a(normals.size(), 3);
    for (size_t i = 0; i < normals.size(); ++i) a.row(Eigen::Index(i)) = normals[i].transpose();
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(Eigen::Index(normals.size()));
    const Vec3 t = a.completeOrthogonalDecomposition().solve(ones);
    if (!t.allFinite() || t.norm() > 4 || (a * t - ones).norm() > 1e-6) return std::nullopt;
    return t;
}

}  // namespace hexmesh
