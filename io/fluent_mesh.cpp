#include "io/fluent_mesh.h"

#include "io/file_sink.h"
#include "io/grid_faces.h"

namespace hexmesh {

void write_fluent_mesh(const BlockGrid& grid, const std::string& path) {
    const GridFaces faces = make_grid_faces(grid);
    const int npatches = int(faces.patch_names.size());
    const Id nodes = Id(grid.points.size()), cells = grid.num_cells();
    const Id nfaces = faces.internal_faces + faces.boundary_faces;
    FileSink out(path, false);
    out.print("(0 \"written by hexmesh: {} hexahedra, {} boundary patches\")\n(2 3)\n", cells,
              npatches);
    out.print("(10 (0 1 {:x} 0 3))\n(10 (1 1 {:x} 1 3)(\n", nodes, nodes);
    for (const Vec3& p : grid.points) out.print("{} {} {}\n", p.x(), p.y(), p.z());
    out.print("))\n(12 (0 1 {:x} 0))\n(12 (2 1 {:x} 1 4))\n(13 (0 1 {:x} 0))\n", cells, cells,
              nfaces);
    // A face as Fluent lists it: nodes, then c0 and c1 (1-based, 0 for no cell), the
    // right-hand rule over the nodes pointing into c0. Our faces point out of their owner
    // (OpenFOAM's convention): reversed, with c0 the owner. A boundary face so points into the
    // domain.
    const auto face = [&](const std::array<Id, 4>& n, Id owner, Id neighbour) {
        out.print("{:x} {:x} {:x} {:x} {:x} {:x}\n", n[3] + 1, n[2] + 1, n[1] + 1, n[0] + 1,
                  owner + 1, neighbour + 1);
    };
    Id first = 1;
    if (faces.internal_faces > 0) {
        out.print("(13 (3 {:x} {:x} 2 4)(\n", first, first + faces.internal_faces - 1);
        for_each_internal_face(grid, faces,
                               [&](Id o, Id n, const std::array<Id, 4>& f) { face(f, o, n); });
        out.print("))\n");
        first += faces.internal_faces;
    }
    const std::vector<Id> counts = patch_face_counts(grid, faces);
    for (int p = 0; p < npatches; ++p) {
        const Id count = counts[size_t(p)];
        out.print("(13 ({:x} {:x} {:x} {:x} 4)(\n", 4 + p, first, first + count - 1,
                  faces.patch_names[p] == "wall" ? 3 : 9);
        for_each_patch_face(grid, faces, p,
                            [&](Id o, const std::array<Id, 4>& f) { face(f, o, -1); });
        out.print("))\n");
        first += count;
    }
    out.print("(45 (2 fluid fluid)())\n(45 (3 interior interior)())\n");
    for (int p = 0; p < npatches; ++p)
        out.print("(45 ({} {} {})())\n", 4 + p,
                  faces.patch_names[p] == "wall" ? "wall" : "pressure-far-field",
                  faces.patch_names[p]);
    out.close();
}

}  // namespace hexmesh
