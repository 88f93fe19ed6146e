#include "io/openfoam_mesh.h"

#include <filesystem>
#include <stdexcept>

#include "io/file_sink.h"
#include "io/grid_faces.h"

namespace hexmesh {
namespace {

namespace fs = std::filesystem;

void write_header(FileSink& out, const char* cls, const char* object, const std::string& note) {
    out.print("/*--------------------------------*- C++ -*----------------------------------*\\\n"
              "  written by hexmesh\n"
              "\\*---------------------------------------------------------------------------*/\n"
              "FoamFile\n{{\n    version     2.0;\n    format      ascii;\n"
              "    class       {};\n", cls);
    if (!note.empty()) out.print("    note        \"{}\";\n", note);
    out.print("    location    \"constant/polyMesh\";\n    object      {};\n}}\n\n", object);
}

void write_footer(FileSink& out) {
    out.print(")\n\n// ************************************************************************* //\n");
}

}  // namespace

void write_openfoam_polymesh(const BlockGrid& grid, const std::string& polymesh_dir) {
    const GridFaces faces = make_grid_faces(grid);
    const Id nfaces = faces.internal_faces + faces.boundary_faces;
    if (nfaces >= (Id(1) << 31) || Id(grid.points.size()) >= (Id(1) << 31))
        throw std::runtime_error(polymesh_dir + ": too large for OpenFOAM's 32-bit labels");
    const fs::path mesh_dir(polymesh_dir);
    std::error_code ec;
    fs::create_directories(mesh_dir, ec);
    if (ec) throw std::runtime_error(fmt::format("{}: cannot create directory ({})", mesh_dir.string(), ec.message()));
    const std::string note = fmt::format("nPoints:{} nCells:{} nFaces:{} nInternalFaces:{}",
                                         grid.points.size(), grid.num_cells(), nfaces,
                                         faces.internal_faces);
    {
        FileSink out((mesh_dir / "points").string());
        write_header(out, "vectorField", "points", "");
        out.print("{}\n(\n", grid.points.size());
        for (const Vec3& p : grid.points) out.print("({} {} {})\n", p.x(), p.y(), p.z());
        write_footer(out);
        out.close();
    }
    {
        FileSink out((mesh_dir / "faces").string());
        write_header(out, "faceList", "faces", "");
        out.print("{}\n(\n", nfaces);
        auto face = [&](const std::array<Id, 4>& n) {
            out.print("4({} {} {} {})\n", n[0], n[1], n[2], n[3]);
        };
        for_each_internal_face(grid, faces, [&](Id, Id, const std::array<Id, 4>& n) { face(n); });
        for (int p = 0; p < int(faces.patch_names.size()); ++p)
            for_each_patch_face(grid, faces, p, [&](Id, const std::array<Id, 4>& n) { face(n); });
        write_footer(out);
        out.close();
    }
    {
        FileSink owner((mesh_dir / "owner").string());
        FileSink neighbour((mesh_dir / "neighbour").string());
        write_header(owner, "labelList", "owner", note);
        write_header(neighbour, "labelList", "neighbour", note);
        owner.print("{}\n(\n", nfaces);
        neighbour.print("{}\n(\n", faces.internal_faces);
        for_each_internal_face(grid, faces, [&](Id o, Id n, const std::array<Id, 4>&) {
            owner.print("{}\n", o);
            neighbour.print("{}\n", n);
        });
        for (int p = 0; p < int(faces.patch_names.size()); ++p)
            for_each_patch_face(grid, faces, p, [&](Id o, const std::array<Id, 4>&) { owner.print("{}\n", o); });
        write_footer(owner);
        write_footer(neighbour);
        owner.close();
        neighbour.close();
    }
    {
        FileSink out((mesh_dir / "boundary").string());
        write_header(out, "polyBoundaryMesh", "boundary", "");
        out.print("{}\n(\n", faces.patch_names.size());
        Id start = faces.internal_faces;
        for (int p = 0; p < int(faces.patch_names.size()); ++p) {
            Id count = 0;
            for_each_patch_face(grid, faces, p, [&](Id, const std::array<Id, 4>&) { ++count; });
            const std::string& name = faces.patch_names[p];
            const char* type = name == "wall" ? "wall" : "patch";
            out.print("    {}\n    {{\n        type            {};\n", name, type);
            if (name == "wall") out.print("        inGroups        List<word> 1(wall);\n");
            out.print("        nFaces          {};\n        startFace       {};\n    }}\n", count, start);
            start += count;
        }
        write_footer(out);
        out.close();
    }
}

void write_openfoam_mesh(const BlockGrid& grid, const std::string& case_dir) {
    write_openfoam_polymesh(grid, (fs::path(case_dir) / "constant" / "polyMesh").string());
    std::error_code ec;
    fs::create_directories(fs::path(case_dir) / "system", ec);
    if (ec) throw std::runtime_error(fmt::format("{}/system: cannot create directory ({})", case_dir, ec.message()));
    // Just enough of system/ for checkMesh and foamToVTK; an existing file is kept.
    auto write_if_absent = [&](const char* name, const std::string& body) {
        const fs::path file = fs::path(case_dir) / "system" / name;
        if (fs::exists(file, ec)) return;
        FileSink out(file.string(), false);
        out.print("FoamFile\n{{\n    version     2.0;\n    format      ascii;\n"
                  "    class       dictionary;\n    location    \"system\";\n"
                  "    object      {};\n}}\n\n{}", name, body);
        out.close();
    };
    write_if_absent("controlDict",
                    "application     simpleFoam;\nstartFrom       startTime;\nstartTime       0;\n"
                    "stopAt          endTime;\nendTime         1;\ndeltaT          1;\n"
                    "writeControl    timeStep;\nwriteInterval   1;\n");
    write_if_absent("fvSchemes",
                    "ddtSchemes { default steadyState; }\ngradSchemes { default Gauss linear; }\n"
                    "divSchemes { default none; }\n"
                    "laplacianSchemes { default Gauss linear corrected; }\n"
                    "interpolationSchemes { default linear; }\nsnGradSchemes { default corrected; }\n");
    write_if_absent("fvSolution", "solvers {}\n");
}

}  // namespace hexmesh
