#include "volume/tet_flips.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <unordered_map>
#include <utility>
#include <vector>

#include "hexmesh/core/array_hash.h"
#include "hexmesh/quality/tet_quality.h"
#include "hexmesh/quality/validity.h"

namespace hexmesh {
namespace {

using Tet = std::array<Id, 4>;
using Face = std::array<Id, 3>;
using Edge = std::array<Id, 2>;

Face face_key(Id a, Id b, Id c) {
    Face f = {a, b, c};
    std::sort(f.begin(), f.end());
    return f;
}
Edge edge_key(Id a, Id b) {
    return a < b ? Edge{a, b} : Edge{b, a};
}

constexpr int tet_edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
// Largest ring of tets around an edge that edge removal tries (7 tets become 10).
constexpr int max_ring = 7;
// A replacement must raise the smallest dihedral angle by more than this (degrees), so that
// round-off cannot make two triangulations flip back and forth.
constexpr double min_gain_degrees = 1e-6;

// The tets with their face and edge incidences, kept up to date as tets come and go.
class Topology {
  public:
    explicit Topology(const TetMesh& mesh) : points_(mesh.points) {
        for (Id t = 0; t < mesh.num_cells(); ++t)
            add({mesh.node(t, 0), mesh.node(t, 1), mesh.node(t, 2), mesh.node(t, 3)});
    }

    const std::vector<Vec3>& points() const { return points_; }
    void add_point(const Vec3& p) { points_.push_back(p); }
    const Tet& tet(Id t) const { return tets_[t]; }
    bool alive(Id t) const { return alive_[t]; }
    Id size() const { return Id(tets_.size()); }
    const std::vector<Id>& around_face(const Face& f) const { return faces_.at(f); }
    const std::vector<Id>* around_edge(const Edge& e) const {
        const auto it = edges_.find(e);
        return it == edges_.end() ? nullptr : &it->second;
    }

    Id add(const Tet& t) {
        const Id id = Id(tets_.size());
        tets_.push_back(t);
        alive_.push_back(true);
        for (int f = 0; f < 4; ++f)
            faces_[face_key(t[(f + 1) % 4], t[(f + 2) % 4], t[(f + 3) % 4])].push_back(id);
        for (const auto& e : tet_edges) edges_[edge_key(t[e[0]], t[e[1]])].push_back(id);
        return id;
    }

    void remove(Id id) {
        const Tet& t = tets_[id];
        alive_[id] = false;
        auto drop = [id](std::vector<Id>& list) {
            const auto it = std::find(list.begin(), list.end(), id);
            assert(it != list.end());
            list.erase(it);
        };
        for (int f = 0; f < 4; ++f) {
            const Face key = face_key(t[(f + 1) % 4], t[(f + 2) % 4], t[(f + 3) % 4]);
            auto& list = faces_[key];
            drop(list);
            if (list.empty()) faces_.erase(key);
        }
        for (const auto& e : tet_edges) {
            const Edge key = edge_key(t[e[0]], t[e[1]]);
            auto& list = edges_[key];
            drop(list);
            if (list.empty()) edges_.erase(key);
        }
    }

    // mesh.tets: the living tets, in the order they were made.
    void write_tets(TetMesh& mesh) const {
        mesh.tets.clear();
        for (Id t : alive_tets())
            mesh.tets.insert(mesh.tets.end(), tets_[t].begin(), tets_[t].end());
    }

    std::vector<Id> alive_tets() const {
        std::vector<Id> out;
        for (Id t = 0; t < size(); ++t)
            if (alive_[t]) out.push_back(t);
        return out;
    }

  private:
    std::vector<Vec3> points_;
    std::vector<Tet> tets_;
    std::vector<bool> alive_;
    std::unordered_map<Face, std::vector<Id>, ArrayHash<Id, 3>> faces_;
    std::unordered_map<Edge, std::vector<Id>, ArrayHash<Id, 2>> edges_;
};

// Every tet positively oriented (exact predicate): what flips and insertion require.
bool all_positive(const TetMesh& mesh) {
    for (Id t = 0; t < mesh.num_cells(); ++t)
        if (exact_orientation(mesh.points[mesh.node(t, 0)], mesh.points[mesh.node(t, 1)],
                              mesh.points[mesh.node(t, 2)], mesh.points[mesh.node(t, 3)]) <= 0)
            return false;
    return true;
}

double smallest_angle(const std::vector<Vec3>& x, const Tet& t) {
    const auto a = dihedral_angles({x[t[0]], x[t[1]], x[t[2]], x[t[3]]});
    return *std::min_element(a.begin(), a.end());
}

// Replaces the tets `old` by `fresh` when that raises the smallest dihedral angle. The
// callers build `fresh` positively oriented (exact predicate) over the same region as `old`:
// edge removal from a closed ring, 2-3 only where the apexes' edge crosses the shared face.
bool try_replace(Topology& topo, const std::vector<Id>& old, const std::vector<Tet>& fresh) {
    const auto& x = topo.points();
    double old_angle = 180, new_angle = 180;
    for (Id t : old) old_angle = std::min(old_angle, smallest_angle(x, topo.tet(t)));
    for (const Tet& t : fresh) new_angle = std::min(new_angle, smallest_angle(x, t));
    if (!(new_angle > old_angle + min_gain_degrees)) return false;
    for (Id t : old) topo.remove(t);
    for (const Tet& t : fresh) topo.add(t);
    return true;
}

// The ring of points around the inner edge ab, in order, with the tets around it; false when
// ab is on the boundary (the ring does not close) or the ring is not a simple cycle.
bool edge_ring(const Topology& topo, Id a, Id b, std::vector<Id>& ring, std::vector<Id>& tets) {
    const std::vector<Id>* around = topo.around_edge(edge_key(a, b));
    if (!around || around->size() < 3 || around->size() > max_ring) return false;
    tets = *around;
    std::vector<Edge> links;  // the two other points of each tet around ab
    for (Id t : tets) {
        Edge l{-1, -1};
        int k = 0;
        for (Id v : topo.tet(t))
            if (v != a && v != b && k < 2) l[k++] = v;
        if (k != 2) return false;  // a tet with a repeated point
        links.push_back(l);
    }
    ring = {links[0][0], links[0][1]};
    std::vector<bool> used(links.size(), false);
    used[0] = true;
    while (ring.size() < links.size()) {
        bool grown = false;
        for (size_t i = 0; i < links.size() && !grown; ++i) {
            if (used[i] || (links[i][0] != ring.back() && links[i][1] != ring.back())) continue;
            const Id next = links[i][0] == ring.back() ? links[i][1] : links[i][0];
            if (std::find(ring.begin(), ring.end(), next) != ring.end()) return false;
            ring.push_back(next);
            used[i] = grown = true;
        }
        if (!grown) return false;
    }
    // The last tet closes the cycle.
    for (size_t i = 0; i < links.size(); ++i)
        if (!used[i])
            return (links[i][0] == ring.back() && links[i][1] == ring.front()) ||
                   (links[i][1] == ring.back() && links[i][0] == ring.front());
    return false;
}

// Edge removal (Shewchuk's generalization of the 3-2 flip): the m tets around the inner edge
// ab become 2m - 4, the triangles of the best triangulation of its ring of points, each joined
// to a and to b. The triangulation maximizes the smallest dihedral angle of the new tets
// (dynamic programming over the ring polygon); diagonals already in the mesh are not used.
bool remove_edge(Topology& topo, Id a, Id b) {
    std::vector<Id> ring, old;
    if (!edge_ring(topo, a, b, ring, old)) return false;
    const auto& x = topo.points();
    const int m = int(ring.size());
    // Smallest angle of the tets (p, q, r, a) and (p, r, q, b) when both have orientation
    // `sign`, else -1 (not allowed).
    auto quality = [&](int i, int j, int k, int sign) {
        const Id p = ring[i], q = ring[j], r = ring[k];
        if (exact_orientation(x[p], x[q], x[r], x[a]) != sign ||
            exact_orientation(x[p], x[r], x[q], x[b]) != sign)
            return -1.0;
        return std::min(smallest_angle(x, {p, q, r, a}), smallest_angle(x, {p, r, q, b}));
    };
    auto usable = [&](int i, int k) {
        return k - i == 1 || (i == 0 && k == m - 1) ||
               !topo.around_edge(edge_key(ring[i], ring[k]));
    };
    std::vector<Tet> best_tets;
    double best = -1;
    for (int sign : {1, -1}) {  // the ring's direction around ab decides which one is valid
        // best_of[i][k]: best smallest angle over the triangulations of ring[i..k]; split[i][k]
        // the apex j of the triangle on the side (i, k).
        std::array<std::array<double, max_ring>, max_ring> best_of;
        std::array<std::array<int, max_ring>, max_ring> split{};
        for (int i = 0; i + 1 < m; ++i) best_of[i][i + 1] = 180;
        for (int span = 2; span < m; ++span)
            for (int i = 0; i + span < m; ++i) {
                const int k = i + span;
                best_of[i][k] = -1;
                if (!usable(i, k)) continue;
                for (int j = i + 1; j < k; ++j) {
                    const double q =
                        std::min({best_of[i][j], best_of[j][k], quality(i, j, k, sign)});
                    if (q > best_of[i][k]) {
                        best_of[i][k] = q;
                        split[i][k] = j;
                    }
                }
            }
        if (best_of[0][m - 1] <= best) continue;
        best = best_of[0][m - 1];
        best_tets.clear();
        std::vector<std::pair<int, int>> todo = {{0, m - 1}};
        while (!todo.empty()) {
            const auto [i, k] = todo.back();
            todo.pop_back();
            if (k - i < 2) continue;
            const int j = split[i][k];
            // Both new tets have orientation `sign`: reversed ones are flipped to positive.
            if (sign > 0) {
                best_tets.push_back({ring[i], ring[j], ring[k], a});
                best_tets.push_back({ring[i], ring[k], ring[j], b});
            } else {
                best_tets.push_back({ring[i], ring[k], ring[j], a});
                best_tets.push_back({ring[i], ring[j], ring[k], b});
            }
            todo.push_back({i, j});
            todo.push_back({j, k});
        }
    }
    return best > 0 && try_replace(topo, old, best_tets);
}

// 2-3: the tets on both sides of the inner face abc become three around the edge of their apexes.
bool flip_23(Topology& topo, Id a, Id b, Id c) {
    const std::vector<Id>& pair = topo.around_face(face_key(a, b, c));
    if (pair.size() != 2) return false;
    Id apex[2] = {-1, -1};
    for (int k = 0; k < 2; ++k)
        for (Id v : topo.tet(pair[k]))
            if (v != a && v != b && v != c) apex[k] = v;
    if (topo.around_edge(edge_key(apex[0], apex[1]))) return false;  // that edge exists elsewhere
    // The three new tets fill the two old ones exactly when the apexes' edge crosses the
    // inside of abc: then all three have the same (non-zero) orientation.
    const auto& x = topo.points();
    std::vector<Tet> fresh = {
        {a, b, apex[0], apex[1]}, {b, c, apex[0], apex[1]}, {c, a, apex[0], apex[1]}};
    const int sign = exact_orientation(x[a], x[b], x[apex[0]], x[apex[1]]);
    for (const Tet& t : fresh)
        if (sign == 0 || exact_orientation(x[t[0]], x[t[1]], x[t[2]], x[t[3]]) != sign)
            return false;
    if (sign < 0)
        for (Tet& t : fresh) std::swap(t[0], t[1]);
    const std::vector<Id> old = pair;
    return try_replace(topo, old, fresh);
}

// The cavity of `levels` rings of tets around tet t across inner faces (level 1: t and its face
// neighbours), its boundary faces each with the tet it belongs to and the slot of the point
// opposite it.
struct Cavity {
    std::vector<Id> tets;
    std::vector<std::pair<Id, int>> faces;  // (tet, slot of the point the new point replaces)
};

Cavity grow_cavity(const Topology& topo, Id t, int levels) {
    Cavity c{{t}, {}};
    for (int level = 0; level < levels; ++level) {
        const size_t end = c.tets.size();
        for (size_t i = 0; i < end; ++i) {
            const Tet& tet = topo.tet(c.tets[i]);
            for (int f = 0; f < 4; ++f)
                for (Id n : topo.around_face(
                         face_key(tet[(f + 1) % 4], tet[(f + 2) % 4], tet[(f + 3) % 4])))
                    if (std::find(c.tets.begin(), c.tets.end(), n) == c.tets.end())
                        c.tets.push_back(n);
        }
    }
    std::unordered_map<Face, int, ArrayHash<Id, 3>> count;
    for (Id id : c.tets) {
        const Tet& tet = topo.tet(id);
        for (int f = 0; f < 4; ++f)
            ++count[face_key(tet[(f + 1) % 4], tet[(f + 2) % 4], tet[(f + 3) % 4])];
    }
    for (Id id : c.tets) {
        const Tet& tet = topo.tet(id);
        for (int f = 0; f < 4; ++f)
            if (count[face_key(tet[(f + 1) % 4], tet[(f + 2) % 4], tet[(f + 3) % 4])] == 1)
                c.faces.push_back({id, f});
    }
    return c;
}

// The tets joining each boundary face of the cavity to point q (index `q` in `x`).
std::vector<Tet> cone(const Topology& topo, const Cavity& c, Id q) {
    std::vector<Tet> fresh;
    for (const auto& [id, slot] : c.faces) {
        Tet t = topo.tet(id);
        t[slot] = q;
        fresh.push_back(t);
    }
    return fresh;
}

// The smallest dihedral angle of the cone of `c` from the point x.back(), or -1 when a tet of
// it is not positively oriented (exact predicate). When all are, the cone fills the cavity
// exactly: the signed tets of a cone over a closed surface cover each point as often as the
// surface winds around it, once inside the cavity.
double cone_quality(const Topology& topo, const Cavity& c, const std::vector<Vec3>& x) {
    const Id q = Id(x.size()) - 1;
    double angle = 180;
    for (const Tet& t : cone(topo, c, q)) {
        if (exact_orientation(x[t[0]], x[t[1]], x[t[2]], x[t[3]]) <= 0) return -1;
        angle = std::min(angle, smallest_angle(x, t));
    }
    return angle;
}

}  // namespace

Id insert_in_slivers(TetMesh& mesh, double below_degrees, const std::vector<bool>& on_boundary) {
    if (!all_positive(mesh)) return 0;
    Topology topo(mesh);
    std::vector<std::pair<double, Id>> poor;
    for (Id t : topo.alive_tets()) {
        const Tet& tet = topo.tet(t);
        const bool pinned =
            std::all_of(tet.begin(), tet.end(), [&](Id v) { return on_boundary[v]; });
        const double angle = smallest_angle(topo.points(), tet);
        if (pinned && angle < below_degrees) poor.push_back({angle, t});
    }
    std::sort(poor.begin(), poor.end());
    std::vector<Vec3> x = topo.points();
    Id inserted = 0;
    for (const auto& [angle, t] : poor) {
        if (!topo.alive(t)) continue;
        for (int levels = 1; levels <= 2; ++levels) {
            const Cavity c = grow_cavity(topo, t, levels);
            // Every point of the cavity must stay on its boundary: none is removed.
            std::vector<Id> kept_points;
            for (const auto& [id, slot] : c.faces)
                for (int k = 0; k < 4; ++k)
                    if (k != slot) kept_points.push_back(topo.tet(id)[k]);
            bool encloses = false;
            double old_angle = 180;
            for (Id id : c.tets) {
                const Tet& tet = topo.tet(id);
                old_angle = std::min(old_angle, smallest_angle(x, tet));
                for (Id v : tet)
                    encloses |=
                        std::find(kept_points.begin(), kept_points.end(), v) == kept_points.end();
            }
            if (encloses) continue;
            // The new point: from the sliver's centroid, a compass search on the cone's
            // smallest angle.
            const Tet& s = topo.tet(t);
            Vec3 best_point = (x[s[0]] + x[s[1]] + x[s[2]] + x[s[3]]) / 4;
            double reach = 0;
            for (int k = 0; k < 4; ++k) reach = std::max(reach, (x[s[k]] - best_point).norm());
            double step = 0.25 * reach;
            x.push_back(best_point);
            double best = cone_quality(topo, c, x);
            for (int iteration = 0; iteration < 60 && step > 1e-3 * reach; ++iteration) {
                bool moved = false;
                for (int axis = 0; axis < 3 && !moved; ++axis)
                    for (double sign : {1.0, -1.0}) {
                        x.back() = best_point + sign * step * Vec3::Unit(axis);
                        const double q = cone_quality(topo, c, x);
                        if (q > best) {
                            best = q, best_point = x.back(), moved = true;
                            break;
                        }
                    }
                if (!moved) step *= 0.5;
            }
            x.back() = best_point;
            if (!(best > old_angle + min_gain_degrees)) {
                x.pop_back();
                continue;
            }
            // The point joins the topology's copy of the points through a rebuilt cone.
            const Id q = Id(x.size()) - 1;
            const std::vector<Tet> fresh = cone(topo, c, q);
            topo.add_point(best_point);
            for (Id id : c.tets) topo.remove(id);
            for (const Tet& tet : fresh) topo.add(tet);
            ++inserted;
            break;
        }
    }
    mesh.points = topo.points();
    topo.write_tets(mesh);
    return inserted;
}

FlipResult improve_by_flips(TetMesh& mesh, double below_degrees, int passes) {
    FlipResult result;
    if (!all_positive(mesh)) return result;
    Topology topo(mesh);
    for (int pass = 0; pass < passes; ++pass) {
        std::vector<std::pair<double, Id>> poor;
        for (Id t : topo.alive_tets()) {
            const double angle = smallest_angle(topo.points(), topo.tet(t));
            if (angle < below_degrees) poor.push_back({angle, t});
        }
        std::sort(poor.begin(), poor.end());
        Id flipped = 0;
        for (const auto& [angle, t] : poor) {
            if (!topo.alive(t)) continue;
            const Tet tet = topo.tet(t);
            bool done = false;
            for (const auto& e : tet_edges)
                if (!done && remove_edge(topo, tet[e[0]], tet[e[1]])) {
                    done = true;
                    ++result.edge_removals;
                }
            for (int f = 0; f < 4 && !done; ++f)
                if (flip_23(topo, tet[(f + 1) % 4], tet[(f + 2) % 4], tet[(f + 3) % 4])) {
                    done = true;
                    ++result.flips_23;
                }
            flipped += done;
        }
        if (flipped == 0) break;
    }
    topo.write_tets(mesh);
    return result;
}

}  // namespace hexmesh
