// `hexmesh inspect SURFACE`: what a surface file holds and whether it bounds a solid.
#include <fmt/format.h>
#include <iostream>
#include <memory>

#include "hexmesh/cli/commands.h"
#include "io/surface_reader.h"
#include "surface/sharp_features.h"
#include "surface/surface_diagnostics.h"

namespace hexmesh::cli {

void add_inspect_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string path;
        double feature_angle = 30;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("inspect", "print the diagnostics of a surface file");
    cmd->add_option("surface", args->path, "surface (.stl .obj .off .ply)")->required();
    cmd->add_option("--feature-angle", args->feature_angle,
                    "crease threshold: dihedral turn in degrees")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 179.0));
    cmd->callback([args, &exit_code] {
        SurfaceReadOptions read;
        read.allow_degenerate = true;  // counted below instead of refused
        const TriangleSurface s = read_surface(args->path, read);
        const SurfaceDiagnostics d = diagnose_surface(s);
        FeatureOptions fo;
        fo.angle_degrees = args->feature_angle;
        const FeatureCurves f = detect_sharp_features(s, fo);
        const Vec3 size = d.bounds.size();
        auto row = [](const char* name, const std::string& value) {
            std::cout << fmt::format("  {:<32}{:>24}\n", name, value);
        };
        std::cout << fmt::format("surface {}\n", args->path);
        row("triangles", fmt::format("{}", d.triangles));
        row("points", fmt::format("{}", d.points));
        row("bounds min", fmt::format("{:.6g} {:.6g} {:.6g}", d.bounds.lo.x(), d.bounds.lo.y(), d.bounds.lo.z()));
        row("bounds max", fmt::format("{:.6g} {:.6g} {:.6g}", d.bounds.hi.x(), d.bounds.hi.y(), d.bounds.hi.z()));
        row("size", fmt::format("{:.6g} {:.6g} {:.6g}", size.x(), size.y(), size.z()));
        row("edges", fmt::format("{}", d.edges));
        row("open (boundary) edges", fmt::format("{}", d.boundary_edges));
        row("non-manifold edges", fmt::format("{}", d.non_manifold_edges));
        row("inconsistently oriented edges", fmt::format("{}", d.inconsistent_edges));
        row("degenerate triangles", fmt::format("{}", d.degenerate_triangles));
        row("self-intersecting pairs", fmt::format("{}", d.self_intersections));
        row(fmt::format("crease chains ({:g} deg)", args->feature_angle).c_str(),
            fmt::format("{}", f.chains.size()));
        row("corners", fmt::format("{}", f.corners.size()));
        if (!d.degenerate_ids.empty()) {
            std::string ids;
            for (int t : d.degenerate_ids) ids += fmt::format("{}{}", ids.empty() ? "" : " ", t);
            row("first degenerate triangles", ids);
        }
        std::cout << (d.watertight() ? "  watertight: yes (closed, manifold, oriented)\n"
                                     : "  watertight: no (the SDF will sign it by winding number "
                                       "if it has open edges)\n");
        exit_code = 0;
    });
}

}  // namespace hexmesh::cli
