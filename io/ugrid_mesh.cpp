#include "io/ugrid_mesh.h"

#include "io/file_sink.h"
#include "io/grid_faces.h"

namespace hexmesh {

std::string ugrid_mapbc_path(const std::string& path) {
    const std::string suffix = ".ugrid";
    const bool ends = path.size() >= suffix.size() &&
                      path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
    return (ends ? path.substr(0, path.size() - suffix.size()) : path) + ".mapbc";
}

void write_ugrid_mesh(const BlockGrid& grid, const std::string& path) {
    const GridFaces faces = make_grid_faces(grid);
    const int npatches = int(faces.patch_names.size());
    {
        FileSink out(path, false);
        out.print("{} 0 {} 0 0 0 {}\n", grid.points.size(), faces.boundary_faces, grid.num_cells());
        for (const Vec3& p : grid.points) out.print("{} {} {}\n", p.x(), p.y(), p.z());
        for (int p = 0; p < npatches; ++p)
            for_each_patch_face(grid, faces, p, [&](Id, const std::array<Id, 4>& n) {
                out.print("{} {} {} {}\n", n[0] + 1, n[1] + 1, n[2] + 1, n[3] + 1);
            });
        for (int p = 0; p < npatches; ++p)
            for_each_patch_face(grid, faces, p,
                                [&](Id, const std::array<Id, 4>&) { out.print("{}\n", p + 1); });
        for (const Block& b : grid.blocks)
            for_each_cell(b, [&](int, int, int, const std::array<Id, 8>& n) {
                out.print("{} {} {} {} {} {} {} {}\n", n[0] + 1, n[1] + 1, n[2] + 1, n[3] + 1,
                          n[4] + 1, n[5] + 1, n[6] + 1, n[7] + 1);
            });
        out.close();
    }
    FileSink map(ugrid_mapbc_path(path), false);
    map.print("{}\n", npatches);
    for (int p = 0; p < npatches; ++p)
        map.print("{} {} {}\n", p + 1, faces.patch_names[p] == "wall" ? 4000 : 5050,
                  faces.patch_names[p]);
    map.close();
}

}  // namespace hexmesh
