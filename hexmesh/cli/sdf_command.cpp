// `hexmesh sdf SURFACE -o FIELD.vdb`: the signed distance field of a surface, for inspection.
#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

#include "hexmesh/cli/commands.h"
#include "hexmesh/pipeline/make_body.h"
#include "surface/mesh_sdf.h"

namespace hexmesh::cli {

void add_sdf_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string input, output;
        double voxel_size = 0;
        int resolution = 256;
        std::string sign = "auto";
        double feature_angle = 30;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("sdf", "write the signed distance field of a surface");
    cmd->add_option("surface", args->input, "surface (.stl .obj .off .ply)")->required();
    cmd->add_option("-o,--output", args->output, "OpenVDB file to write (.vdb)")->required();
    cmd->add_option("--voxel-size", args->voxel_size,
                    "voxel edge in geometry units (default: longest side / resolution)");
    cmd->add_option("--resolution", args->resolution, "voxels along the longest side")
        ->capture_default_str()
        ->check(CLI::Range(2, 100000));
    cmd->add_option("--sign", args->sign, "inside test: auto, flood-fill or winding-number")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "flood-fill", "winding-number"}));
    cmd->add_option("--feature-angle", args->feature_angle,
                    "edges turning more than this are sharp creases (degrees; 180: none)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 180.0));
    cmd->callback([args, &exit_code] {
        if (args->voxel_size < 0) throw InputError("--voxel-size: expected a positive number");
        const auto start = std::chrono::steady_clock::now();
        std::string note;
        const TriangleSurface surface = read_surface_file(args->input, &note);
        if (!note.empty()) std::cout << note << "\n";
        MeshSdfOptions options;
        options.voxel_size = args->voxel_size;
        options.resolution = args->resolution;
        options.feature_angle = args->feature_angle;
        options.sign = args->sign == "flood-fill"       ? SdfSign::flood_fill
                       : args->sign == "winding-number" ? SdfSign::winding_number
                                                        : SdfSign::automatic;
        const MeshSdf sdf = naming_file(args->input, [&] { return MeshSdf(surface, options); });
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // Written under a temporary name and renamed: no half-written file on failure.
        const std::filesystem::path out(args->output), partial(args->output + ".partial");
        sdf.write_vdb(partial.string());
        std::filesystem::rename(partial, out);
        std::cout << fmt::format("sdf of {} ({} triangles)\n", args->input,
                                 surface.triangles.size())
                  << fmt::format("  voxel size        {:.6g}\n", sdf.voxel_size())
                  << fmt::format("  sign              {}\n",
                                 sdf.signed_by_winding_number() ? "winding number" : "flood fill")
                  << fmt::format("  sharp creases     {} edges, {} corners\n",
                                 sdf.creases().crease_edges(), sdf.creases().corners())
                  << fmt::format("  active voxels     {}\n", sdf.active_voxels())
                  << fmt::format("  memory            {:.1f} MB\n", sdf.memory_bytes() / 1e6)
                  << fmt::format("  read + build      {:.2f} s\n", seconds)
                  << fmt::format("written: {}\n", out.string());
        exit_code = 0;
    });
}

}  // namespace hexmesh::cli
