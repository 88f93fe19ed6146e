#include "io/export_grid.h"

#include <fmt/format.h>

#include <filesystem>

#include "io/case_file.h"
#include "io/cgns_grid.h"
#include "io/exodus_mesh.h"
#include "io/fluent_mesh.h"
#include "io/gmsh_mesh.h"
#include "io/medit_mesh.h"
#include "io/openfoam_mesh.h"
#include "io/plot3d.h"
#include "io/staged_output.h"
#include "io/su2_mesh.h"
#include "io/ugrid_mesh.h"
#include "io/vtk_mesh.h"

namespace hexmesh {
namespace {

namespace fs = std::filesystem;

bool parse_plot3d(const std::string& format, Plot3dFormat& out) {
    if (format.rfind("plot3d", 0) != 0) return false;
    std::string rest = format.substr(6);
    out = {};
    if (rest.size() >= 7 && rest.compare(rest.size() - 7, 7, "-single") == 0) {
        out.single_precision = true;
        rest.resize(rest.size() - 7);
    }
    if (rest.empty() || rest == "-fortran")
        out.encoding = Plot3dEncoding::fortran;
    else if (rest == "-c")
        out.encoding = Plot3dEncoding::c_binary;
    else if (rest == "-ascii")
        out.encoding = Plot3dEncoding::ascii;
    else
        return false;
    return true;
}

std::string lower_extension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace

bool is_export_format(const std::string& format) {
    Plot3dFormat p;
    return format == "vtk" || format == "openfoam" || format == "cgns" || format == "gmsh" ||
           format == "medit" || format == "su2" || format == "ugrid" || format == "fluent" ||
           format == "exodus" || parse_plot3d(format, p);
}

std::string export_format_list() {
    return "vtk, openfoam, cgns, gmsh, medit, su2, ugrid, fluent, exodus, "
           "plot3d[-fortran|-c|-ascii][-single]";
}

std::string export_file_name(const std::string& format, const std::string& stem,
                             const BlockGrid& grid) {
    if (format == "vtk") return stem + (grid.blocks.size() == 1 ? ".vts" : ".vtm");
    if (format == "openfoam") return stem + "_openfoam";
    if (format == "cgns") return stem + ".cgns";
    if (format == "gmsh") return stem + ".msh";
    if (format == "medit") return stem + ".mesh";
    if (format == "su2") return stem + ".su2";
    if (format == "ugrid") return stem + ".ugrid";
    if (format == "fluent") return stem + "_fluent.msh";
    if (format == "exodus") return stem + ".exo";
    if (format == "plot3d") return stem + ".xyz";
    std::string variant = format.substr(std::string("plot3d-").size());
    for (char& c : variant) c = c == '-' ? '_' : c;
    return stem + "_" + variant + ".xyz";
}

void write_grid_format(const BlockGrid& grid, const std::string& format, const std::string& path,
                       const FlowSpec& flow) {
    Plot3dFormat plot3d;
    if (format == "vtk")
        write_vtk_grid(grid, path);
    else if (format == "openfoam")
        write_openfoam_mesh(grid, path, flow);
    else if (format == "cgns")
        write_cgns_grid(grid, path);
    else if (format == "gmsh")
        write_gmsh_mesh(grid, path);
    else if (format == "medit")
        write_medit_mesh(grid, path);
    else if (format == "su2")
        write_su2_mesh(grid, path);
    else if (format == "ugrid")
        write_ugrid_mesh(grid, path);
    else if (format == "fluent")
        write_fluent_mesh(grid, path);
    else if (format == "exodus")
        write_exodus_mesh(grid, path);
    else if (parse_plot3d(format, plot3d))
        write_plot3d(grid, path, plot3d);
    else
        throw InputError(fmt::format("unknown export format '{}' (expected one of: {})", format,
                                     export_format_list()));
}

std::vector<std::string> export_grid(const BlockGrid& grid, const std::string& format,
                                     const std::string& path, const FlowSpec& flow) {
    if (!is_export_format(format))
        throw InputError(fmt::format("unknown export format '{}' (expected one of: {})", format,
                                     export_format_list()));
    const fs::path target(path);
    if (target.filename().empty() || target.filename() == "." || target.filename() == "..")
        throw InputError(fmt::format("{}: expected a file name to write", path));
    std::error_code ec;
    if (format == "openfoam" && fs::is_directory(target, ec)) {
        // An existing case keeps its other files: only constant/polyMesh is replaced.
        StagedOutput out((target / "constant").string(), StagedOutput::Scope::named_entries);
        write_openfoam_polymesh(grid, out.path("polyMesh"));
        return out.commit();
    }
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    StagedOutput out(folder.string(),
                     StagedOutput::Scope::named_entries);  // the user's folder: one file
    write_grid_format(grid, format, out.path(target.filename().string()), flow);
    if (format == "ugrid")
        out.path(ugrid_mapbc_path(target.filename().string()));  // written beside it
    if (format.rfind("plot3d", 0) == 0) {
        out.path(plot3d_patch_file(target.filename().string()));
        out.path(plot3d_map_file(target.filename().string()));
    }
    return out.commit();
}

bool is_plot3d_path(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".xyz" || ext == ".x" || ext == ".p3d" || ext == ".g";
}

BlockGrid read_block_grid(const std::string& path) {
    if (is_plot3d_path(path)) return read_plot3d(path);
    const std::string ext = lower_extension(path);
    if (ext == ".vts" || ext == ".vtm") return read_vtk_block_grid(path);
    throw InputError(
        fmt::format("{}: not a block grid (expected .vts, .vtm or Plot3D .xyz .x .p3d .g)", path));
}

}  // namespace hexmesh
