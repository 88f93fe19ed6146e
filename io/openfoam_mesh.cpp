#include "io/openfoam_mesh.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "io/file_sink.h"
#include "io/grid_faces.h"

namespace hexmesh {
namespace {

namespace fs = std::filesystem;

void write_header(FileSink& out, const char* cls, const char* object, const std::string& note) {
    out.print(
        "/*--------------------------------*- C++ -*----------------------------------*\\\n"
        "  written by hexmesh\n"
        "\\*---------------------------------------------------------------------------*/\n"
        "FoamFile\n{{\n    version     2.0;\n    format      ascii;\n"
        "    class       {};\n",
        cls);
    if (!note.empty()) out.print("    note        \"{}\";\n", note);
    out.print("    location    \"constant/polyMesh\";\n    object      {};\n}}\n\n", object);
}

void write_footer(FileSink& out) {
    out.print(
        ")\n\n// ************************************************************************* //\n");
}

// Point numbers in the order the blocks first reach them (block by block, i fastest): the same
// for a grid held in memory and for that grid read back from its VTK files, whose merged
// points come in another order.
std::vector<Id> point_numbers(const BlockGrid& grid, std::vector<Id>& order) {
    std::vector<Id> number(grid.points.size(), -1);
    order.clear();
    for (const Block& b : grid.blocks)
        for (const Id v : b.node_ids)
            if (number[v] < 0) number[v] = Id(order.size()), order.push_back(v);
    return number;
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
    if (ec)
        throw std::runtime_error(
            fmt::format("{}: cannot create directory ({})", mesh_dir.string(), ec.message()));
    std::vector<Id> order;
    const std::vector<Id> number = point_numbers(grid, order);
    const std::string note =
        fmt::format("nPoints:{} nCells:{} nFaces:{} nInternalFaces:{}", order.size(),
                    grid.num_cells(), nfaces, faces.internal_faces);
    {
        FileSink out((mesh_dir / "points").string());
        write_header(out, "vectorField", "points", "");
        out.print("{}\n(\n", order.size());
        for (const Id v : order) {
            const Vec3& p = grid.points[v];
            out.print("({} {} {})\n", p.x(), p.y(), p.z());
        }
        write_footer(out);
        out.close();
    }
    {
        FileSink out((mesh_dir / "faces").string());
        write_header(out, "faceList", "faces", "");
        out.print("{}\n(\n", nfaces);
        auto face = [&](const std::array<Id, 4>& n) {
            out.print("4({} {} {} {})\n", number[n[0]], number[n[1]], number[n[2]], number[n[3]]);
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
            for_each_patch_face(grid, faces, p,
                                [&](Id o, const std::array<Id, 4>&) { owner.print("{}\n", o); });
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
        const std::vector<Id> counts = patch_face_counts(grid, faces);
        for (int p = 0; p < int(faces.patch_names.size()); ++p) {
            const Id count = counts[size_t(p)];
            const std::string& name = faces.patch_names[p];
            const char* type = name == "wall" ? "wall" : "patch";
            out.print("    {}\n    {{\n        type            {};\n", name, type);
            if (name == "wall") out.print("        inGroups        List<word> 1(wall);\n");
            out.print("        nFaces          {};\n        startFace       {};\n    }}\n", count,
                      start);
            start += count;
        }
        write_footer(out);
        out.close();
    }
}

namespace {

// The far-field values of k and omega for the SST model: k = 1.5 (I |U|)^2, omega =
// sqrt(k) / (Cmu^(1/4) l), l the mixing length (given, or a tenth of the wall's largest extent).
struct TurbulenceInflow {
    double k = 0, omega = 0;
};

TurbulenceInflow turbulence_inflow(const BlockGrid& grid, const GridFaces& faces,
                                   const FlowSpec& flow) {
    double length = flow.turbulence_length;
    if (!(length > 0)) {
        Box3 box{Vec3::Constant(1e300), Vec3::Constant(-1e300)};
        for (int p = 0; p < int(faces.patch_names.size()); ++p)
            if (faces.patch_names[p] == "wall")
                for_each_patch_face(grid, faces, p, [&](Id, const std::array<Id, 4>& n) {
                    for (Id v : n)
                        box.lo = box.lo.cwiseMin(grid.points[v]),
                        box.hi = box.hi.cwiseMax(grid.points[v]);
                });
        length = box.hi.x() >= box.lo.x() ? 0.1 * (box.hi - box.lo).maxCoeff() : 0.1;
    }
    TurbulenceInflow t;
    const double u = flow.turbulence_intensity * flow.velocity.norm();
    t.k = std::max(1.5 * u * u, 1e-12);
    t.omega = std::sqrt(t.k) / (std::pow(0.09, 0.25) * length);
    return t;
}

// One field file of 0/: the internal value and, per patch, the wall's or the far field's
// condition ("{value}" in them stands for the internal value).
std::string field_file(const char* cls, const char* object, const char* dimensions,
                       const std::string& value, const std::vector<std::string>& patches,
                       const std::string& wall, const std::string& far) {
    std::string text = fmt::format(
        "FoamFile\n{{\n    version     2.0;\n    format      ascii;\n"
        "    class       {};\n    location    \"0\";\n    object      {};\n}}\n\n"
        "dimensions      {};\n\ninternalField   uniform {};\n\nboundaryField\n{{\n",
        cls, object, dimensions, value);
    for (const std::string& patch : patches) {
        std::string condition = patch == "wall" ? wall : far;
        for (size_t at; (at = condition.find("{value}")) != std::string::npos;)
            condition.replace(at, 7, value);
        text += fmt::format("    {}\n    {{\n{}    }}\n", patch, condition);
    }
    return text + "}\n";
}

std::string dictionary(const char* location, const char* object, const std::string& body) {
    return fmt::format(
        "FoamFile\n{{\n    version     2.0;\n    format      ascii;\n"
        "    class       dictionary;\n    location    \"{}\";\n    object      {};\n}}\n\n{}",
        location, object, body);
}

// Writes `text` as `relative` in the case folder, only where that file is absent: a user's own
// dictionaries are kept.
void write_if_absent(const std::string& case_dir, const std::string& relative,
                     const std::string& text) {
    std::error_code ec;
    const fs::path file = fs::path(case_dir) / relative;
    if (fs::exists(file, ec)) return;
    fs::create_directories(file.parent_path(), ec);
    if (ec)
        throw std::runtime_error(fmt::format("{}: cannot create directory ({})",
                                             file.parent_path().string(), ec.message()));
    FileSink out(file.string(), false);
    out.print("{}", text);
    out.close();
}

// system/: controlDict, fvSchemes and fvSolution of a steady simpleFoam run.
void write_system_dictionaries(const std::string& case_dir) {
    write_if_absent(
        case_dir, "system/controlDict",
        dictionary("system", "controlDict",
                   "application     simpleFoam;\nstartFrom       latestTime;\nstartTime       0;\n"
                   "stopAt          endTime;\nendTime         2000;\ndeltaT          1;\n"
                   "writeControl    timeStep;\nwriteInterval   200;\npurgeWrite      2;\n"
                   "writeFormat     ascii;\nwritePrecision  8;\ntimeFormat      general;\n"
                   "runTimeModifiable true;\n"));
    write_if_absent(
        case_dir, "system/fvSchemes",
        dictionary(
            "system", "fvSchemes",
            "ddtSchemes { default steadyState; }\n"
            "gradSchemes { default Gauss linear; grad(U) cellLimited Gauss linear 1; }\n"
            "divSchemes\n{\n    default none;\n    div(phi,U) bounded Gauss linearUpwind grad(U);\n"
            "    div(phi,k) bounded Gauss upwind;\n    div(phi,omega) bounded Gauss upwind;\n"
            "    div((nuEff*dev2(T(grad(U))))) Gauss linear;\n}\n"
            "laplacianSchemes { default Gauss linear limited corrected 0.5; }\n"
            "interpolationSchemes { default linear; }\n"
            "snGradSchemes { default limited corrected 0.5; }\n"
            "wallDist { method meshWave; }\n"));
    write_if_absent(
        case_dir, "system/fvSolution",
        dictionary("system", "fvSolution",
                   "solvers\n{\n    p { solver GAMG; smoother GaussSeidel; tolerance 1e-7; relTol "
                   "0.05; }\n"
                   "    \"(U|k|omega)\" { solver smoothSolver; smoother symGaussSeidel; tolerance "
                   "1e-8; relTol 0.1; }\n}\n"
                   "SIMPLE\n{\n    nNonOrthogonalCorrectors 1;\n    consistent      yes;\n"
                   "    pRefCell        0;\n    pRefValue       0;\n"
                   "    residualControl { p 1e-5; U 1e-6; \"(k|omega)\" 1e-6; }\n}\n"
                   "relaxationFactors { equations { U 0.9; \".*\" 0.7; } }\n"));
}

// constant/: transportProperties (the kinematic viscosity) and turbulenceProperties (k-omega
// SST or laminar).
void write_constant_dictionaries(const std::string& case_dir, const FlowSpec& flow, bool sst) {
    write_if_absent(case_dir, "constant/transportProperties",
                    dictionary("constant", "transportProperties",
                               fmt::format("transportModel  Newtonian;\nnu              {};\n",
                                           flow.viscosity / flow.density)));
    write_if_absent(
        case_dir, "constant/turbulenceProperties",
        dictionary("constant", "turbulenceProperties",
                   sst ? "simulationType  RAS;\nRAS\n{\n    RASModel        kOmegaSST;\n"
                         "    turbulence      on;\n    printCoeffs     on;\n}\n"
                       : "simulationType  laminar;\n"));
}

// 0/: the initial and boundary values of U and p, and with k-omega SST of k, omega and nut.
void write_initial_fields(const std::string& case_dir, const BlockGrid& grid,
                          const GridFaces& faces, const FlowSpec& flow, bool sst) {
    const Vec3& u = flow.velocity;
    const std::string velocity = fmt::format("({} {} {})", u.x(), u.y(), u.z());
    const std::vector<std::string>& patches = faces.patch_names;
    write_if_absent(case_dir, "0/U",
                    field_file("volVectorField", "U", "[0 1 -1 0 0 0 0]", velocity, patches,
                               "        type            noSlip;\n",
                               "        type            freestreamVelocity;\n"
                               "        freestreamValue uniform {value};\n        value     "
                               "      uniform {value};\n"));
    write_if_absent(case_dir, "0/p",
                    field_file("volScalarField", "p", "[0 2 -2 0 0 0 0]", "0", patches,
                               "        type            zeroGradient;\n",
                               "        type            freestreamPressure;\n"
                               "        freestreamValue uniform {value};\n        value     "
                               "      uniform {value};\n"));
    if (sst) {
        const TurbulenceInflow t = turbulence_inflow(grid, faces, flow);
        const std::string inlet_outlet =
            "        type            inletOutlet;\n        inletValue      uniform {value};\n"
            "        value           uniform {value};\n";
        write_if_absent(
            case_dir, "0/k",
            field_file("volScalarField", "k", "[0 2 -2 0 0 0 0]", fmt::format("{}", t.k), patches,
                       "        type            kqRWallFunction;\n        value "
                       "          uniform {value};\n",
                       inlet_outlet));
        write_if_absent(case_dir, "0/omega",
                        field_file("volScalarField", "omega", "[0 0 -1 0 0 0 0]",
                                   fmt::format("{}", t.omega), patches,
                                   "        type            omegaWallFunction;\n        "
                                   "value           uniform {value};\n",
                                   inlet_outlet));
        write_if_absent(
            case_dir, "0/nut",
            field_file(
                "volScalarField", "nut", "[0 2 -1 0 0 0 0]", "0", patches,
                "        type            nutkWallFunction;\n        value           uniform 0;\n",
                "        type            calculated;\n        value           uniform 0;\n"));
    }
}

}  // namespace

void write_openfoam_mesh(const BlockGrid& grid, const std::string& case_dir, const FlowSpec& flow) {
    write_openfoam_polymesh(grid, (fs::path(case_dir) / "constant" / "polyMesh").string());
    const GridFaces faces = make_grid_faces(grid);
    const bool sst = flow.turbulence == "k-omega-sst";
    write_system_dictionaries(case_dir);
    write_constant_dictionaries(case_dir, flow, sst);
    write_initial_fields(case_dir, grid, faces, flow, sst);
}

}  // namespace hexmesh
