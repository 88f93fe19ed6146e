#include "surface/point_cloud.h"

#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>

#include <boost/iterator/counting_iterator.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hexmesh {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;

// Point index -> its position, so that the tree stores indices.
struct PointMap {
    using key_type = std::size_t;
    using value_type = Point;
    using reference = const Point&;
    using category = boost::readable_property_map_tag;
    const std::vector<Point>* points = nullptr;
    friend reference get(const PointMap& m, std::size_t i) { return (*m.points)[i]; }
};

using Traits = CGAL::Search_traits_adapter<std::size_t, PointMap, CGAL::Search_traits_3<Kernel>>;
using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;

}  // namespace

struct PointCloudSdf::Tree {
    std::vector<Point> points;
    std::unique_ptr<Search::Tree> tree;
    PointMap map() const { return {&points}; }
};

PointCloudSdf::PointCloudSdf(const OrientedPoints& cloud, const PointCloudSdfOptions& options)
    : tree_(std::make_unique<Tree>()), neighbours_(options.neighbours) {
    const size_t n = cloud.points.size();
    if (n == 0) throw std::invalid_argument("PointCloudSdf: no point");
    if (cloud.normals.size() != n)
        throw std::invalid_argument("PointCloudSdf: " + std::to_string(n) + " points but " +
                                    std::to_string(cloud.normals.size()) + " normals");
    if (options.neighbours < 1 || options.neighbours > 64 || !(options.bandwidth >= 0))
        throw std::invalid_argument("PointCloudSdf: neighbours must be in 1..64, bandwidth >= 0");
    bounds_ = {cloud.points[0], cloud.points[0]};
    tree_->points.reserve(n);
    normals_.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        const Vec3 &p = cloud.points[i], &normal = cloud.normals[i];
        if (!p.allFinite() || !normal.allFinite() || !(normal.norm() > 0))
            throw std::invalid_argument("PointCloudSdf: point " + std::to_string(i) +
                                        " has a non-finite coordinate or a zero normal");
        tree_->points.emplace_back(p.x(), p.y(), p.z());
        normals_.push_back(normal.normalized());
        bounds_.lo = bounds_.lo.cwiseMin(p);
        bounds_.hi = bounds_.hi.cwiseMax(p);
    }
    tree_->tree = std::make_unique<Search::Tree>(boost::counting_iterator<std::size_t>(0),
                                                 boost::counting_iterator<std::size_t>(n),
                                                 Search::Tree::Splitter(), Traits(tree_->map()));
    tree_->tree->build();  // once, here: concurrent queries must not build it lazily

    // The spacing: the mean distance to the nearest other point.
    const Search::Distance distance(tree_->map());
    double sum = 0;
    for (size_t i = 0; i < n && n > 1; ++i) {
        const Search search(*tree_->tree, tree_->points[i], 2, 0, true, distance);
        for (auto it = search.begin(); it != search.end(); ++it)
            if (it->first != i) {
                sum += std::sqrt(it->second);
                break;
            }
    }
    mean_spacing_ = n > 1 ? sum / double(n) : 0;
    bandwidth_ = options.bandwidth > 0 ? options.bandwidth : mean_spacing_;
    if (!(bandwidth_ > 0)) bandwidth_ = 1e-3 * std::max(1.0, bounds_.diagonal());
    const double margin = 3 * bandwidth_ + 0.01 * bounds_.diagonal();
    bounds_.lo.array() -= margin;
    bounds_.hi.array() += margin;
}

PointCloudSdf::~PointCloudSdf() = default;

double PointCloudSdf::evaluate(const Vec3& x, Vec3* gradient) const {
    const Search::Distance distance(tree_->map());
    const Search search(*tree_->tree, Point(x.x(), x.y(), x.z()), neighbours_ + 1, 0, true,
                        distance);
    // Squared distances in increasing order; the (k+1)-th one is R^2.
    struct Near {
        std::size_t id;
        double d2;
    };
    Near near[65];
    int count = 0;
    for (auto it = search.begin(); it != search.end() && count < 65; ++it)
        near[count++] = {it->first, it->second};
    const int k = std::min(count, neighbours_);
    const double r2 = count > neighbours_ ? near[neighbours_].d2
                                          : 4 * near[count - 1].d2 + bandwidth_ * bandwidth_;
    const double h2 = bandwidth_ * bandwidth_, d2_min = near[0].d2;
    // Falls back to plain Gaussian weights when every neighbour is at distance R (the
    // centre of a sampled sphere).
    const bool taper = r2 > d2_min;
    double weight[64], plane[64], sum_w = 0, u = 0;
    for (int m = 0; m < k; ++m) {
        const double t = taper ? std::max(0.0, 1 - near[m].d2 / r2) : 1.0;
        weight[m] = std::exp(-(near[m].d2 - d2_min) / h2) * t * t;  // shifted: no underflow
        const Vec3 p(tree_->points[near[m].id].x(), tree_->points[near[m].id].y(),
                     tree_->points[near[m].id].z());
        plane[m] = normals_[near[m].id].dot(x - p);
        sum_w += weight[m];
        u += weight[m] * plane[m];
    }
    u /= sum_w;
    if (!gradient) return u;
    // grad u = sum_i w_i (n_i + (a_i - u) grad log w_i) / sum_i w_i, with
    // log w_i = 2 log(1 - d_i^2 / R^2) - d_i^2 / h^2 + const and R^2 = |x - p_(k+1)|^2.
    const auto position = [&](int m) {
        const Point& q = tree_->points[near[m].id];
        return Vec3(q.x(), q.y(), q.z());
    };
    const bool has_r = taper && count > neighbours_;
    const Vec3 to_r = has_r ? Vec3(x - position(neighbours_)) : Vec3::Zero();
    Vec3 g = Vec3::Zero();
    for (int m = 0; m < k; ++m) {
        if (weight[m] == 0) continue;
        const Vec3 d = x - position(m);
        Vec3 log_w = -2 * d / h2;
        if (taper) {
            const double t = 1 - near[m].d2 / r2;
            log_w += (2 / t) * (-2 * d / r2 + (has_r ? 2 * near[m].d2 / (r2 * r2) : 0.0) * to_r);
        }
        g += weight[m] * (normals_[near[m].id] + (plane[m] - u) * log_w);
    }
    *gradient = g / sum_w;
    return u;
}

double PointCloudSdf::value(const Vec3& p) const {
    return evaluate(p, nullptr);
}

Vec3 PointCloudSdf::gradient(const Vec3& p) const {
    Vec3 g;
    evaluate(p, &g);
    return g;
}

Box3 PointCloudSdf::bounds() const {
    return bounds_;
}

PointCloudDiagnostics diagnose_point_cloud(const OrientedPoints& cloud, int neighbours) {
    const size_t n = cloud.points.size();
    if (cloud.normals.size() != n)
        throw std::invalid_argument("diagnose_point_cloud: " + std::to_string(n) + " points but " +
                                    std::to_string(cloud.normals.size()) + " normals");
    if (neighbours < 1 || neighbours > 64)
        throw std::invalid_argument("diagnose_point_cloud: neighbours must be in 1..64");
    PointCloudDiagnostics d;
    d.points = (long long)n;
    if (n == 0) return d;
    d.bounds = {cloud.points[0], cloud.points[0]};
    std::vector<Point> points;
    points.reserve(n);
    for (const Vec3& p : cloud.points) {
        points.emplace_back(p.x(), p.y(), p.z());
        d.bounds.lo = d.bounds.lo.cwiseMin(p);
        d.bounds.hi = d.bounds.hi.cwiseMax(p);
    }
    if (n == 1) return d;
    const PointMap map{&points};
    Search::Tree tree(boost::counting_iterator<std::size_t>(0),
                      boost::counting_iterator<std::size_t>(n), Search::Tree::Splitter(),
                      Traits(map));
    tree.build();
    const Search::Distance distance(map);
    const double same = 1e-12 * std::max(d.bounds.diagonal(), 1e-300);
    double sum = 0;
    for (size_t i = 0; i < n; ++i) {
        const Search search(tree, points[i], unsigned(neighbours) + 1, 0, true, distance);
        double nearest = -1;
        Vec3 summed = Vec3::Zero();
        for (auto it = search.begin(); it != search.end(); ++it) {
            if (it->first == i) continue;
            if (nearest < 0) nearest = std::sqrt(it->second);
            const Vec3& normal = cloud.normals[it->first];
            if (normal.norm() > 0) summed += normal.normalized();
        }
        sum += nearest;
        d.largest_gap = std::max(d.largest_gap, nearest);
        d.duplicates += nearest <= same;
        d.inconsistent_normals += summed.dot(cloud.normals[i]) < 0;
    }
    d.mean_spacing = sum / double(n);
    return d;
}

}  // namespace hexmesh
