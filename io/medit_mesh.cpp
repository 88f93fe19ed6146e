#include "io/medit_mesh.h"

#include "io/file_sink.h"
#include "io/grid_faces.h"
#include "io/text_tokens.h"

namespace hexmesh {

void write_medit_mesh(const BlockGrid& grid, const std::string& path) {
    const GridFaces faces = make_grid_faces(grid);
    FileSink out(path, false);
    out.print("MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n{}\n", grid.points.size());
    for (const Vec3& p : grid.points) out.print("{} {} {} 0\n", p.x(), p.y(), p.z());
    out.print("\n");
    for (int p = 0; p < int(faces.patch_names.size()); ++p)
        out.print("# patch {} {}\n", p + 1, faces.patch_names[p]);
    out.print("Quadrilaterals\n{}\n", faces.boundary_faces);
    for (int p = 0; p < int(faces.patch_names.size()); ++p)
        for_each_patch_face(grid, faces, p, [&](Id, const std::array<Id, 4>& n) {
            out.print("{} {} {} {} {}\n", n[0] + 1, n[1] + 1, n[2] + 1, n[3] + 1, p + 1);
        });
    out.print("\nHexahedra\n{}\n", grid.num_cells());
    for (const Block& b : grid.blocks)
        for_each_cell(b, [&](int, int, int, const std::array<Id, 8>& n) {
            out.print("{} {} {} {} {} {} {} {} 1\n", n[0] + 1, n[1] + 1, n[2] + 1, n[3] + 1,
                      n[4] + 1, n[5] + 1, n[6] + 1, n[7] + 1);
        });
    out.print("\nEnd\n");
    out.close();
}

HexMesh read_medit_mesh(const std::string& path) {
    TextTokens in(path);
    HexMesh mesh;
    bool seen_version = false;
    // Number of integers after the vertex ids of an element keyword: 1 (its reference).
    auto skip_elements = [&](int per_element) {
        const long long n = in.integer("an element count");
        if (n < 0 || n > (long long)in.size())
            in.fail(fmt::format("{} elements do not fit in the file", n));
        for (long long e = 0; e < n * per_element; ++e) in.integer("an element entry");
    };
    while (!in.done()) {
        const std::string key = in.word();
        if (key[0] == '#') {
            in.skip_line();
        } else if (key == "MeshVersionFormatted") {
            in.integer("the version");
            seen_version = true;
        } else if (key == "Dimension") {
            if (in.integer("the dimension") != 3) in.fail("only 3D meshes are supported");
        } else if (key == "Vertices") {
            const long long n = in.integer("the vertex count");
            for (long long v = 0; v < n; ++v) {
                const double x = in.real("x"), y = in.real("y"), z = in.real("z");
                in.integer("a vertex reference");
                mesh.points.emplace_back(x, y, z);
            }
        } else if (key == "Hexahedra") {
            const long long n = in.integer("the hexahedron count");
            for (long long e = 0; e < n; ++e) {
                for (int v = 0; v < 8; ++v) {
                    const long long id = in.integer("a vertex number");
                    if (id < 1 || id > mesh.num_points())
                        in.fail(fmt::format("hexahedron {} uses vertex {} (have {})", e + 1, id,
                                            mesh.num_points()));
                    mesh.hexes.push_back(id - 1);
                }
                in.integer("a hexahedron reference");
            }
        } else if (key == "Edges") {
            skip_elements(3);
        } else if (key == "Triangles") {
            skip_elements(4);
        } else if (key == "Quadrilaterals" || key == "Tetrahedra") {
            skip_elements(5);
        } else if (key == "End") {
            break;
        } else {
            in.fail(fmt::format("unsupported keyword '{}'", key));
        }
    }
    if (!seen_version) in.fail("not a Medit mesh (no MeshVersionFormatted)");
    if (mesh.num_cells() == 0) in.fail("the file holds no hexahedra");
    return mesh;
}

}  // namespace hexmesh
