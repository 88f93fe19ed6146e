#include "surface/exact_distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace hexmesh {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<Kernel::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Kernel::Point_3 to_cgal(const Vec3& p) {
    return {p.x(), p.y(), p.z()};
}

}  // namespace

struct ExactDistance::Tree {
    Triangles triangles;     // must outlive the tree, which holds iterators into it
    std::vector<int> index;  // of each in the surface's triangles (degenerate ones are left out)
    AabbTree tree;
};

ExactDistance::ExactDistance(const TriangleSurface& surface)
    : tree_(std::make_unique<Tree>()), surface_(surface) {
    for (size_t i = 0; i < surface.triangles.size(); ++i) {
        const auto& t = surface.triangles[i];
        const Kernel::Triangle_3 tri(to_cgal(surface.points[t[0]]), to_cgal(surface.points[t[1]]),
                                     to_cgal(surface.points[t[2]]));
        if (tri.is_degenerate()) continue;
        tree_->triangles.push_back(tri);
        tree_->index.push_back(int(i));
    }
    if (tree_->triangles.empty())
        throw std::invalid_argument("ExactDistance: no triangle of non-zero area");
    tree_->tree.insert(tree_->triangles.begin(), tree_->triangles.end());
    tree_->tree.build();
    tree_->tree.accelerate_distance_queries();
    tree_->tree.closest_point(to_cgal(surface.points[0]));  // builds the search structure now
}

ExactDistance::~ExactDistance() = default;

double ExactDistance::distance(const Vec3& p) const {
    return std::sqrt(tree_->tree.squared_distance(to_cgal(p)));
}

Vec3 ExactDistance::closest_point(const Vec3& p) const {
    const Kernel::Point_3 c = tree_->tree.closest_point(to_cgal(p));
    return {c.x(), c.y(), c.z()};
}

Vec3 ExactDistance::closest_normal(const Vec3& p) const {
    const auto hit = tree_->tree.closest_point_and_primitive(to_cgal(p));
    const Kernel::Triangle_3& t = *hit.second;
    const Kernel::Vector_3 n = CGAL::cross_product(t[1] - t[0], t[2] - t[0]);
    return Vec3(n.x(), n.y(), n.z()).normalized();
}

int ExactDistance::closest_triangle(const Vec3& p) const {
    const auto hit = tree_->tree.closest_point_and_primitive(to_cgal(p));
    return tree_->index[size_t(hit.second - tree_->triangles.cbegin())];
}

double ExactDistance::winding_number(const Vec3& p) const {
    // Van Oosterom and Strackee's solid angle of each triangle seen from p.
    double total = 0;
    for (const auto& t : surface_.triangles) {
        const Vec3 a = surface_.points[t[0]] - p, b = surface_.points[t[1]] - p,
                   c = surface_.points[t[2]] - p;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        const double numerator = a.dot(b.cross(c));
        const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        total += 2 * std::atan2(numerator, denominator);
    }
    constexpr double pi = 3.14159265358979323846;
    return total / (4 * pi);
}

double ExactDistance::signed_distance(const Vec3& p) const {
    const double d = distance(p);
    return winding_number(p) > 0.5 ? -d : d;
}

double max_distance_to(const ExactDistance& surface, const std::vector<Vec3>& points) {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, points.size()), 0.0,
        [&](const tbb::blocked_range<size_t>& r, double worst) {
            for (size_t k = r.begin(); k != r.end(); ++k)
                worst = std::max(worst, surface.distance(points[k]));
            return worst;
        },
        [](double a, double b) { return std::max(a, b); });
}

}  // namespace hexmesh
