// The `quality`, `report` and `compare` jobs: a mesh file measured — a block grid against the
// case it was built for, a hex or tet mesh on its own — and its report page.
#pragma once

#include <optional>
#include <string>

#include "hexmesh/quality/grid_report.h"
#include "io/report_page.h"
#include "volume/tet_mesh.h"

namespace hexmesh {

// A block grid file (.vtm, .vts: what `run` writes).
bool is_block_grid_file(const std::string& path);

// The case file a block grid at `grid_path` is measured against: `case_path` if given, else
// the grid.case.json `run` writes beside a grid, if any ("" for none).
std::string case_of_grid(const std::string& grid_path, const std::string& case_path);

// A file of tetrahedra only (legacy VTK or VTK XML unstructured), else nullopt.
std::optional<TetMesh> read_tet_mesh(const std::string& path);

// The largest distance of `mesh`'s boundary points to the body of the case file `case_path`,
// in its tet mesh's wall cell sizes.
double tet_boundary_distance(const TetMesh& mesh, const std::string& case_path);

// The report of a hexahedral mesh file: a block grid with a case (case_of_grid) measured
// against its body and wall law (the wall's distance to a surface file, follows_body), else
// its cells alone. `settings`, if given, gets the case as JSON (empty without one). Throws
// InputError for a `case_path` given with a file that is no block grid.
GridReport hex_file_report(const std::string& path, const std::string& case_path,
                           std::string* settings = nullptr);

// The report page of any mesh file, titled by its path: a tet mesh, a block grid (drawn, and
// measured as hex_file_report says) or a hex mesh. Throws InputError for a missing file.
ReportPage page_of_mesh(const std::string& path, const std::string& case_path);

}  // namespace hexmesh
