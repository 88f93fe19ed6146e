#include "io/openfoam_mesh.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
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

namespace {

// A boundary patch as written: its name, the lines of its boundary entry after the name (its
// type and what goes with it), and its faces (owner cell, nodes oriented outwards).
struct BoundaryPatch {
    std::string name, entry;
    std::vector<std::pair<Id, std::array<Id, 4>>> faces;
};

// The boundary entry of a patch of the whole grid: "wall" is a wall, every other a patch.
std::string patch_entry(const std::string& name) {
    return name == "wall" ? "        type            wall;\n        inGroups        List<word> "
                            "1(wall);\n"
                          : "        type            patch;\n";
}

// points, faces, owner, neighbour and boundary of `grid` (its internal faces from `faces`,
// its boundary faces those of `patches`, in order) in `polymesh_dir`.
void write_polymesh(const BlockGrid& grid, const GridFaces& faces,
                    const std::vector<BoundaryPatch>& patches, const std::string& polymesh_dir) {
    Id boundary_faces = 0;
    for (const BoundaryPatch& p : patches) boundary_faces += Id(p.faces.size());
    const Id nfaces = faces.internal_faces + boundary_faces;
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
        for (const BoundaryPatch& p : patches)
            for (const auto& f : p.faces) face(f.second);
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
        for (const BoundaryPatch& p : patches)
            for (const auto& f : p.faces) owner.print("{}\n", f.first);
        write_footer(owner);
        write_footer(neighbour);
        owner.close();
        neighbour.close();
    }
    {
        FileSink out((mesh_dir / "boundary").string());
        write_header(out, "polyBoundaryMesh", "boundary", "");
        out.print("{}\n(\n", patches.size());
        Id start = faces.internal_faces;
        for (const BoundaryPatch& p : patches) {
            out.print(
                "    {}\n    {{\n{}        nFaces          {};\n        startFace       {};\n    "
                "}}\n",
                p.name, p.entry, p.faces.size(), start);
            start += Id(p.faces.size());
        }
        write_footer(out);
        out.close();
    }
}

}  // namespace

void write_openfoam_polymesh(const BlockGrid& grid, const std::string& polymesh_dir) {
    const GridFaces faces = make_grid_faces(grid);
    std::vector<BoundaryPatch> patches;
    for (int p = 0; p < int(faces.patch_names.size()); ++p) {
        BoundaryPatch& patch = patches.emplace_back();
        patch.name = faces.patch_names[size_t(p)];
        patch.entry = patch_entry(patch.name);
        for_each_patch_face(grid, faces, p, [&](Id owner, const std::array<Id, 4>& n) {
            patch.faces.emplace_back(owner, n);
        });
    }
    write_polymesh(grid, faces, patches, polymesh_dir);
}

void write_openfoam_processor_polymesh(const BlockGrid& share, const ProcessorShare& p,
                                       const std::string& polymesh_dir) {
    const GridFaces faces = make_grid_faces(share);
    std::vector<BoundaryPatch> patches(p.patches.size());
    for (size_t q = 0; q < patches.size(); ++q)
        patches[q].name = p.patches[q], patches[q].entry = patch_entry(p.patches[q]);
    // The faces shared with each other process, under their sorted ids in the whole grid.
    using Keyed = std::pair<std::array<Id, 4>, std::pair<Id, std::array<Id, 4>>>;
    std::map<int, std::vector<Keyed>> shared;
    for (int q = 0; q < int(faces.patch_names.size()); ++q) {
        const std::string& name = faces.patch_names[size_t(q)];
        const auto global = std::find(p.patches.begin(), p.patches.end(), name);
        for_each_patch_face_at(
            share, faces, q,
            [&](int b, int face, int i, int j, int k, Id owner, std::array<Id, 4> n) {
                const bool open = share.blocks[size_t(b)].face_patch[size_t(face)] ==
                                  ProcessorShare::shared_faces;
                const int other = open ? p.process_across(b, face, i, j, k) : -1;
                if (other < 0 || other == p.process) {
                    if (global == p.patches.end())
                        throw std::logic_error(
                            fmt::format("{}: a face of block {} meets no cell of another process",
                                        polymesh_dir, share.blocks[size_t(b)].name));
                    patches[size_t(global - p.patches.begin())].faces.emplace_back(owner, n);
                    return;
                }
                // Both processes list the face from its node of lowest id, oriented out of their
                // own cells: each side's face is the other's reversed, from the same node.
                const auto gid = [&](Id v) { return p.global_ids[size_t(v)]; };
                const int first =
                    int(std::min_element(n.begin(), n.end(),
                                         [&](Id a, Id c) { return gid(a) < gid(c); }) -
                        n.begin());
                std::rotate(n.begin(), n.begin() + first, n.end());
                std::array<Id, 4> key;
                for (int m = 0; m < 4; ++m) key[size_t(m)] = gid(n[size_t(m)]);
                std::sort(key.begin(), key.end());
                shared[other].push_back({key, {owner, n}});
            });
    }
    for (auto& [other, list] : shared) {
        std::sort(list.begin(), list.end(),
                  [](const Keyed& a, const Keyed& c) { return a.first < c.first; });
        BoundaryPatch& patch = patches.emplace_back();
        patch.name = fmt::format("procBoundary{}to{}", p.process, other);
        patch.entry = fmt::format(
            "        type            processor;\n        inGroups        List<word> "
            "1(processor);\n        matchTolerance  0.0001;\n        transform       unknown;\n"
            "        myProcNo        {};\n        neighbProcNo    {};\n",
            p.process, other);
        for (const Keyed& f : list) patch.faces.push_back(f.second);
    }
    write_polymesh(share, faces, patches, polymesh_dir);
}

namespace {

// The far-field values of k and omega for the SST model: k = 1.5 (I |U|)^2, omega =
// sqrt(k) / (Cmu^(1/4) l), l the mixing length (given, or a tenth of the wall's largest extent).
struct TurbulenceInflow {
    double k = 0, omega = 0;
};

TurbulenceInflow turbulence_inflow(double wall_extent, const FlowSpec& flow) {
    double length = flow.turbulence_length;
    if (!(length > 0)) length = wall_extent > 0 ? 0.1 * wall_extent : 0.1;
    TurbulenceInflow t;
    const double u = flow.turbulence_intensity * flow.velocity.norm();
    t.k = std::max(1.5 * u * u, 1e-12);
    t.omega = std::sqrt(t.k) / (std::pow(0.09, 0.25) * length);
    return t;
}

// One field file of 0/: the internal value and, per patch, the wall's or the far field's
// condition ("{value}" in them stands for the internal value).
// With `processors`, the processor patches of a decomposed case too.
std::string field_file(const char* cls, const char* object, const char* dimensions,
                       const std::string& value, const std::vector<std::string>& patches,
                       const std::string& wall, const std::string& far, bool processors) {
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
    if (processors)
        text += fmt::format(
            "    \"procBoundary.*\"\n    {{\n        type            processor;\n"
            "        value           uniform {};\n    }}\n",
            value);
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

// 0/: the initial and boundary values of U and p, and with k-omega SST of k, omega and nut, for
// `patches` (and with `processors`, a decomposed case's processor patches); the mixing length
// from the wall's largest extent.
void write_initial_fields(const std::string& case_dir, const std::vector<std::string>& patches,
                          double wall_extent, const FlowSpec& flow, bool processors) {
    const Vec3& u = flow.velocity;
    const std::string velocity = fmt::format("({} {} {})", u.x(), u.y(), u.z());
    auto write = [&](const char* file, const char* cls, const char* dimensions,
                     const std::string& value, const std::string& wall, const std::string& far) {
        write_if_absent(case_dir, std::string("0/") + file,
                        field_file(cls, file, dimensions, value, patches, wall, far, processors));
    };
    write("U", "volVectorField", "[0 1 -1 0 0 0 0]", velocity, "        type            noSlip;\n",
          "        type            freestreamVelocity;\n        freestreamValue uniform "
          "{value};\n        value           uniform {value};\n");
    write("p", "volScalarField", "[0 2 -2 0 0 0 0]", "0", "        type            zeroGradient;\n",
          "        type            freestreamPressure;\n        freestreamValue uniform "
          "{value};\n        value           uniform {value};\n");
    if (flow.turbulence != "k-omega-sst") return;
    const TurbulenceInflow t = turbulence_inflow(wall_extent, flow);
    const std::string inlet_outlet =
        "        type            inletOutlet;\n        inletValue      uniform {value};\n"
        "        value           uniform {value};\n";
    write("k", "volScalarField", "[0 2 -2 0 0 0 0]", fmt::format("{}", t.k),
          "        type            kqRWallFunction;\n        value           uniform {value};\n",
          inlet_outlet);
    write("omega", "volScalarField", "[0 0 -1 0 0 0 0]", fmt::format("{}", t.omega),
          "        type            omegaWallFunction;\n        value           uniform {value};\n",
          inlet_outlet);
    write("nut", "volScalarField", "[0 2 -1 0 0 0 0]", "0",
          "        type            nutkWallFunction;\n        value           uniform 0;\n",
          "        type            calculated;\n        value           uniform 0;\n");
}

}  // namespace

double wall_extent(const BlockGrid& grid) {
    const GridFaces faces = make_grid_faces(grid);
    Box3 box{Vec3::Constant(1e300), Vec3::Constant(-1e300)};
    for (int p = 0; p < int(faces.patch_names.size()); ++p)
        if (faces.patch_names[size_t(p)] == "wall")
            for_each_patch_face(grid, faces, p, [&](Id, const std::array<Id, 4>& n) {
                for (Id v : n)
                    box.lo = box.lo.cwiseMin(grid.points[v]),
                    box.hi = box.hi.cwiseMax(grid.points[v]);
            });
    return box.hi.x() >= box.lo.x() ? (box.hi - box.lo).maxCoeff() : 0;
}

void write_openfoam_mesh(const BlockGrid& grid, const std::string& case_dir, const FlowSpec& flow) {
    write_openfoam_polymesh(grid, (fs::path(case_dir) / "constant" / "polyMesh").string());
    const bool sst = flow.turbulence == "k-omega-sst";
    write_system_dictionaries(case_dir);
    write_constant_dictionaries(case_dir, flow, sst);
    write_initial_fields(case_dir, make_grid_faces(grid).patch_names, wall_extent(grid), flow,
                         false);
}

void write_openfoam_processor(const BlockGrid& share, const ProcessorShare& p,
                              const std::string& case_dir, const FlowSpec& flow) {
    const fs::path processor = fs::path(case_dir) / fmt::format("processor{}", p.process);
    write_openfoam_processor_polymesh(share, p, (processor / "constant" / "polyMesh").string());
    write_initial_fields(processor.string(), p.patches, p.wall_extent, flow, true);
    if (p.process != 0) return;
    write_system_dictionaries(case_dir);
    write_constant_dictionaries(case_dir, flow, flow.turbulence == "k-omega-sst");
    write_if_absent(
        case_dir, "system/decomposeParDict",
        dictionary("system", "decomposeParDict",
                   fmt::format("numberOfSubdomains {};\nmethod          scotch;\n", p.processes)));
}

}  // namespace hexmesh
