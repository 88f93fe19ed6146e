// Grid export: the format names of `hexmesh export` and case `outputs`, written all or nothing.
#pragma once

#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "io/flow_spec.h"

namespace hexmesh {

// Format names: vtk, openfoam, cgns, gmsh, medit, su2, ugrid, fluent, exodus, and
// plot3d[-fortran|-c|-ascii][-single] (plot3d alone is Fortran-unformatted, double precision).
bool is_export_format(const std::string& format);
std::string export_format_list();  // the names above, for messages

// Output name of a format for grid files named `stem` in a folder: stem.vtm (stem.vts for one
// block), stem_openfoam (a case folder), stem.cgns, stem.msh, stem.mesh, stem.su2, stem.ugrid (and
// stem.mapbc), stem_fluent.msh, stem.exo, stem.xyz for plot3d and stem_<variant>.xyz for its other
// variants (plot3d-c-single -> stem_c_single.xyz).
std::string export_file_name(const std::string& format, const std::string& stem,
                             const BlockGrid& grid);

// Writes `grid` in `format` at `path` directly (no staging). Plot3D adds PATH.patches.json;
// an OpenFOAM case is set up for `flow`.
void write_grid_format(const BlockGrid& grid, const std::string& format, const std::string& path,
                       const FlowSpec& flow = {});

// `hexmesh export`: writes into a staging folder beside `path`, then renames into place, so an
// error (unwritable folder, full disk) leaves nothing under the final name. Returns the final
// paths written. Throws InputError for an unknown format, std::runtime_error on write errors.
std::vector<std::string> export_grid(const BlockGrid& grid, const std::string& format,
                                     const std::string& path, const FlowSpec& flow = {});

// Reads a block grid for export: .vts/.vtm (read_vtk_block_grid) or Plot3D (.xyz .x .p3d .g).
BlockGrid read_block_grid(const std::string& path);

// True for the extensions read as Plot3D grids: .xyz .x .p3d .g
bool is_plot3d_path(const std::string& path);

}  // namespace hexmesh
