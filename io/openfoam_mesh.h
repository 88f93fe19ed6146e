// OpenFOAM polyMesh writer: a block grid as points, faces, owner, neighbour and boundary.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "hexmesh/core/block_grid.h"
#include "io/flow_spec.h"

namespace hexmesh {

// Writes `grid` as an OpenFOAM case folder that simpleFoam runs as written:
// CASE/constant/polyMesh/{points, faces, owner, neighbour, boundary} (ASCII, FoamFile
// headers), and for `flow` constant/{transportProperties, turbulenceProperties},
// system/{controlDict, fvSchemes, fvSolution} and 0/{U, p} (k, omega and nut for
// k-omega-sst). Points are numbered as the blocks first reach them (block order, i fastest), so
// a grid and the same grid read back from its VTK files give the same files. Internal faces
// come first in upper-triangular order (ascending owner, then neighbour), each oriented from
// owner to neighbour; boundary faces follow, grouped by patch, oriented outwards. Patch "wall"
// has type wall (noSlip, wall functions), every other patch type patch and a free-stream
// condition (freestreamVelocity / freestreamPressure, inletOutlet for k and omega). The
// dictionaries and fields are written only where absent. Throws std::runtime_error naming the
// file on a write error.
void write_openfoam_mesh(const BlockGrid& grid, const std::string& case_dir,
                         const FlowSpec& flow = {});

// The same polyMesh files directly in `polymesh_dir` (created if missing), nothing else.
void write_openfoam_polymesh(const BlockGrid& grid, const std::string& polymesh_dir);

// One process's share of a grid decomposed for a parallel solver run (mpirun -np N simpleFoam
// -parallel): some of its blocks, with their points numbered on their own.
struct ProcessorShare {
    int process = 0, processes = 1;
    // The whole grid's patches in order (GridFaces::patch_names of the whole grid): every
    // processor lists them all, those without faces here too.
    std::vector<std::string> patches;
    std::vector<Id> global_ids;  // each point's id in the whole grid
    // The patch name the share's block faces without patch (interfaces) take: where no block
    // of the share meets them, they face other processes' cells.
    static constexpr const char* shared_faces = "(other processes)";
    // The process holding the cell across face `face` (BlockFace order) of cell (i, j, k) of
    // block b of the share, on a block face of patch shared_faces that no block of the share
    // matches; -1 where no cell is across (a boundary face).
    std::function<int(int b, int face, int i, int j, int k)> process_across;
    double wall_extent = 0;  // of the whole grid (wall_extent): sets k-omega SST's inflow
};

// Process p.process's polyMesh in `polymesh_dir` (CASE/processorN/constant/polyMesh): its
// cells and points as write_openfoam_polymesh numbers them in `share`, the whole grid's
// patches, then a processor patch procBoundaryNtoM per process M it shares faces with (in
// order of M). Both sides list those faces in the same order (by their nodes' ids in the
// whole grid), each from the node of lowest id, oriented out of its own cells: one side's
// face is the other's reversed from the same node, as OpenFOAM's decomposePar writes them.
void write_openfoam_processor_polymesh(const BlockGrid& share, const ProcessorShare& p,
                                       const std::string& polymesh_dir);

// A decomposed case, one process's part: CASE/processorN/constant/polyMesh
// (write_openfoam_processor_polymesh) and CASE/processorN/0 (the fields of
// write_openfoam_mesh, with the processor patches); process 0 also writes CASE/system (with
// decomposeParDict: N subdomains) and CASE/constant's dictionaries. The case runs as
// `mpirun -np N simpleFoam -parallel`; reconstructParMesh gathers the grid.
void write_openfoam_processor(const BlockGrid& share, const ProcessorShare& p,
                              const std::string& case_dir, const FlowSpec& flow = {});

// The largest extent of the bounding box of `grid`'s "wall" faces (0 without any): the
// mixing length of k-omega SST's inflow is a tenth of it.
double wall_extent(const BlockGrid& grid);

}  // namespace hexmesh
