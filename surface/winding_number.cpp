#include "surface/winding_number.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace hexmesh {
namespace {

constexpr int leaf_size = 8;
constexpr double four_pi = 4 * 3.14159265358979323846;

// Van Oosterom and Strackee: the signed solid angle of triangle abc seen from p.
double solid_angle(const Vec3& pa, const Vec3& pb, const Vec3& pc, const Vec3& p) {
    const Vec3 a = pa - p, b = pb - p, c = pc - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    return 2 * std::atan2(a.dot(b.cross(c)),
                          la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
}

}  // namespace

WindingNumber::WindingNumber(const TriangleSurface& surface, double accuracy)
    : surface_(surface), accuracy_(accuracy) {
    order_.resize(surface_.triangles.size());
    for (int t = 0; t < (int)order_.size(); ++t) order_[t] = t;
    nodes_.reserve(2 * order_.size() / leaf_size + 2);
    if (!order_.empty()) build(0, (int)order_.size());
}

int WindingNumber::build(int first, int count) {
    const auto& pts = surface_.points;
    Node node;
    node.lo = Vec3::Constant(1e300);
    node.hi = Vec3::Constant(-1e300);
    node.normal = Vec3::Zero();
    Vec3 weighted = Vec3::Zero();
    double area = 0;
    for (int k = first; k < first + count; ++k) {
        const auto& t = surface_.triangles[order_[k]];
        Vec3 sum = Vec3::Zero();
        for (int c = 0; c < 3; ++c) {
            node.lo = node.lo.cwiseMin(pts[t[c]]);
            node.hi = node.hi.cwiseMax(pts[t[c]]);
            sum += pts[t[c]];
        }
        const Vec3 n = 0.5 * (pts[t[1]] - pts[t[0]]).cross(pts[t[2]] - pts[t[0]]);
        node.normal += n;
        weighted += n.norm() * sum / 3;
        area += n.norm();
    }
    node.centre = area > 0 ? Vec3(weighted / area) : Vec3(0.5 * (node.lo + node.hi));
    node.radius = 0;
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 q((corner & 1 ? node.hi : node.lo).x(), (corner & 2 ? node.hi : node.lo).y(),
                     (corner & 4 ? node.hi : node.lo).z());
        node.radius = std::max(node.radius, (q - node.centre).norm());
    }
    node.first = first;
    node.count = count;
    const int id = (int)nodes_.size();
    nodes_.push_back(node);
    if (count <= leaf_size) return id;

    // Median split of the centroids along the longest side of the box.
    int axis = 0;
    (node.hi - node.lo).maxCoeff(&axis);
    auto key = [&](int t) {
        const auto& tri = surface_.triangles[t];
        return pts[tri[0]][axis] + pts[tri[1]][axis] + pts[tri[2]][axis];
    };
    const int half = count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + first + half,
                     order_.begin() + first + count, [&](int a, int b) { return key(a) < key(b); });
    const int left = build(first, half);
    const int right = build(first + half, count - half);
    nodes_[id].left = left;
    nodes_[id].right = right;
    return id;
}

double WindingNumber::operator()(const Vec3& p) const {
    if (nodes_.empty()) return 0;
    double total = 0;
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = nodes_[stack[--top]];
        const Vec3 r = n.centre - p;
        const double d = r.norm();
        if (d > accuracy_ * n.radius) {
            total += n.normal.dot(r) / (d * d * d);  // dipole: far cluster as one patch
        } else if (n.left < 0) {
            for (int k = n.first; k < n.first + n.count; ++k) {
                const auto& t = surface_.triangles[order_[k]];
                total += solid_angle(surface_.points[t[0]], surface_.points[t[1]],
                                     surface_.points[t[2]], p);
            }
        } else {
            stack[top++] = n.left;
            stack[top++] = n.right;
        }
    }
    return total / four_pi;
}

}  // namespace hexmesh
