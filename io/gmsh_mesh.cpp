#include "io/gmsh_mesh.h"

#include <string>
#include <unordered_map>
#include <vector>

#include "io/file_sink.h"
#include "io/grid_faces.h"
#include "io/text_tokens.h"

namespace hexmesh {

void write_gmsh_mesh(const BlockGrid& grid, const std::string& path) {
    const GridFaces faces = make_grid_faces(grid);
    const int npatches = int(faces.patch_names.size());
    const int fluid = npatches + 1;  // physical tag of the volume; patches are 1..npatches
    Vec3 lo = Vec3::Constant(0), hi = Vec3::Constant(0);
    if (!grid.points.empty()) lo = hi = grid.points[0];
    for (const Vec3& p : grid.points) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const Id nodes = Id(grid.points.size()), cells = grid.num_cells();

    FileSink out(path, false);
    out.print("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    out.print("$PhysicalNames\n{}\n", npatches + 1);
    for (int p = 0; p < npatches; ++p) out.print("2 {} \"{}\"\n", p + 1, faces.patch_names[p]);
    out.print("3 {} \"fluid\"\n$EndPhysicalNames\n", fluid);

    // Entities: surfaces 1..npatches (one per patch), volume 1 bounded by all of them.
    out.print("$Entities\n0 0 {} 1\n", npatches);
    for (int p = 0; p < npatches; ++p)
        out.print("{} {} {} {} {} {} {} 1 {} 0\n", p + 1, lo.x(), lo.y(), lo.z(), hi.x(), hi.y(),
                  hi.z(), p + 1);
    out.print("1 {} {} {} {} {} {} 1 {} {}", lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z(), fluid,
              npatches);
    for (int p = 0; p < npatches; ++p) out.print(" {}", p + 1);
    out.print("\n$EndEntities\n");

    out.print("$Nodes\n1 {} 1 {}\n3 1 0 {}\n", nodes, nodes, nodes);
    for (Id v = 0; v < nodes; ++v) out.print("{}\n", v + 1);
    for (const Vec3& p : grid.points) out.print("{} {} {}\n", p.x(), p.y(), p.z());
    out.print("$EndNodes\n");

    const std::vector<Id> patch_faces = patch_face_counts(grid, faces);
    const Id elements = cells + faces.boundary_faces;
    out.print("$Elements\n{} {} 1 {}\n", npatches + 1, elements, elements);
    out.print("3 1 5 {}\n", cells);
    Id tag = 1;
    for (const Block& b : grid.blocks)
        for_each_cell(b, [&](int, int, int, const std::array<Id, 8>& n) {
            out.print("{} {} {} {} {} {} {} {} {}\n", tag++, n[0] + 1, n[1] + 1, n[2] + 1, n[3] + 1,
                      n[4] + 1, n[5] + 1, n[6] + 1, n[7] + 1);
        });
    for (int p = 0; p < npatches; ++p) {
        out.print("2 {} 3 {}\n", p + 1, patch_faces[p]);
        for_each_patch_face(grid, faces, p, [&](Id, const std::array<Id, 4>& n) {
            out.print("{} {} {} {} {}\n", tag++, n[0] + 1, n[1] + 1, n[2] + 1, n[3] + 1);
        });
    }
    out.print("$EndElements\n");
    out.close();
}

namespace {

// Node tag -> index in mesh.points: a table when the tags are dense, else a hash map (a max tag
// of 3e9 for a handful of nodes must not take 24 GB).
struct NodeTags {
    std::vector<Id> dense;
    std::unordered_map<long long, Id> sparse;

    // The node of tag `t`, or -1.
    Id node_of(long long t) const {
        if (!dense.empty()) return t >= 1 && t < Id(dense.size()) ? dense[t] : -1;
        const auto it = sparse.find(t);
        return it == sparse.end() ? -1 : it->second;
    }
};

// The $MeshFormat section after its name: version 4.1, ASCII.
void read_format(TextTokens& in) {
    const std::string version = in.word();
    if (version != "4.1")
        in.fail(fmt::format("MSH version {} is not supported (expected 4.1)", version));
    if (in.integer("the file type") != 0) in.fail("binary MSH is not supported (expected ASCII)");
    in.integer("the data size");
}

// The $Nodes section after its name: its points appended to `mesh`, their tags to `tags`.
void read_nodes(TextTokens& in, NodeTags& tags, HexMesh& mesh) {
    const long long blocks = in.integer("numEntityBlocks");
    const long long count = in.integer("numNodes");
    in.integer("minNodeTag");
    const long long max_tag = in.integer("maxNodeTag");
    // A node takes at least 8 characters (its tag and three coordinates).
    if (count < 0 || count > (long long)(in.size() / 8) || blocks < 0 || blocks > count)
        in.fail(fmt::format("{} nodes in {} blocks do not fit in the file's {} bytes", count,
                            blocks, in.size()));
    if (max_tag < 1 && count > 0) in.fail(fmt::format("maxNodeTag {} is below 1", max_tag));
    if (max_tag <= 4 * count + 1024) tags.dense.assign(max_tag + 1, -1);
    tags.sparse.reserve(tags.dense.empty() ? size_t(count) : 0);
    for (long long b = 0; b < blocks; ++b) {
        in.integer("entityDim");
        in.integer("entityTag");
        if (in.integer("parametric") != 0) in.fail("parametric nodes are not supported");
        const long long n = in.integer("numNodesInBlock");
        if (n < 0 || n > count)
            in.fail(fmt::format("a block of {} nodes in a file of {}", n, count));
        std::vector<long long> block_tags(n);
        for (auto& t : block_tags) {
            t = in.integer("a node tag");
            if (t < 1 || t > max_tag)
                in.fail(fmt::format("node tag {} outside [1, {}]", t, max_tag));
        }
        for (long long t : block_tags) {
            const double x = in.real("x"), y = in.real("y"), z = in.real("z");
            if (tags.dense.empty())
                tags.sparse[t] = mesh.num_points();
            else
                tags.dense[t] = mesh.num_points();
            mesh.points.emplace_back(x, y, z);
        }
    }
}

// The $Elements section after its name: its hexahedra appended to `mesh`, the other elements
// skipped.
void read_elements(TextTokens& in, const NodeTags& tags, HexMesh& mesh) {
    const long long blocks = in.integer("numEntityBlocks");
    in.integer("numElements");
    in.integer("minElementTag");
    in.integer("maxElementTag");
    for (long long b = 0; b < blocks; ++b) {
        in.integer("entityDim");
        in.integer("entityTag");
        const long long type = in.integer("elementType");
        const long long n = in.integer("numElementsInBlock");
        for (long long e = 0; e < n; ++e) {
            in.integer("an element tag");
            if (type != 5) {
                in.skip_line();
                continue;
            }
            for (int v = 0; v < 8; ++v) {
                const long long t = in.integer("a node tag");
                const Id node = tags.node_of(t);
                if (node < 0) in.fail(fmt::format("hexahedron uses unknown node {}", t));
                mesh.hexes.push_back(node);
            }
        }
    }
}

}  // namespace

HexMesh read_gmsh_mesh(const std::string& path) {
    TextTokens in(path);
    HexMesh mesh;
    NodeTags tags;
    bool seen_format = false, seen_nodes = false;
    while (!in.done()) {
        const std::string section = in.word();
        if (section == "$MeshFormat") {
            read_format(in);
            seen_format = true;
        } else if (section == "$Nodes") {
            if (!seen_format) in.fail("$Nodes before $MeshFormat");
            if (seen_nodes) in.fail("a second $Nodes section");
            seen_nodes = true;
            read_nodes(in, tags, mesh);
        } else if (section == "$Elements") {
            read_elements(in, tags, mesh);
        } else if (section.size() > 1 && section[0] == '$' && section.rfind("$End", 0) != 0) {
            // A section we do not need: skip to its $End line.
            const std::string end = "$End" + section.substr(1);
            while (!in.done() && in.word() != end) {
            }
        }
    }
    if (!seen_format) in.fail("not a Gmsh file (no $MeshFormat)");
    if (mesh.num_cells() == 0) in.fail("the file holds no hexahedra");
    return mesh;
}

}  // namespace hexmesh
