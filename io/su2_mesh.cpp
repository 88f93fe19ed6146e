#include "io/su2_mesh.h"

#include "io/file_sink.h"
#include "io/grid_faces.h"

namespace hexmesh {

void write_su2_mesh(const BlockGrid& grid, const std::string& path) {
    const GridFaces faces = make_grid_faces(grid);
    FileSink out(path, false);
    out.print("% written by hexmesh: {} hexahedra, {} boundary patches\nNDIME= 3\nNELEM= {}\n",
              grid.num_cells(), faces.patch_names.size(), grid.num_cells());
    Id cell = 0;
    for (const Block& b : grid.blocks)
        for_each_cell(b, [&](int, int, int, const std::array<Id, 8>& n) {
            out.print("12 {} {} {} {} {} {} {} {} {}\n", n[0], n[1], n[2], n[3], n[4], n[5], n[6],
                      n[7], cell++);
        });
    out.print("NPOIN= {}\n", grid.points.size());
    for (size_t v = 0; v < grid.points.size(); ++v) {
        const Vec3& p = grid.points[v];
        out.print("{} {} {} {}\n", p.x(), p.y(), p.z(), v);
    }
    out.print("NMARK= {}\n", faces.patch_names.size());
    const std::vector<Id> counts = patch_face_counts(grid, faces);
    for (int p = 0; p < int(faces.patch_names.size()); ++p) {
        out.print("MARKER_TAG= {}\nMARKER_ELEMS= {}\n", faces.patch_names[p], counts[size_t(p)]);
        for_each_patch_face(grid, faces, p, [&](Id, const std::array<Id, 4>& n) {
            out.print("9 {} {} {} {}\n", n[0], n[1], n[2], n[3]);
        });
    }
    out.close();
}

}  // namespace hexmesh
