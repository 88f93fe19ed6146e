// `hexmesh inspect FILE`: what a surface, point cloud or cross-section file holds and whether
// it bounds a solid.
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "hexmesh/cli/commands.h"
#include "io/sample_readers.h"
#include "io/surface_reader.h"
#include "surface/cross_sections.h"
#include "surface/point_cloud.h"
#include "surface/sharp_features.h"
#include "surface/surface_diagnostics.h"

namespace hexmesh::cli {

namespace {

void row(const std::string& name, const std::string& value) {
    std::cout << fmt::format("  {:<32}{:>24}\n", name, value);
}

void bounds_rows(const Box3& b) {
    const Vec3 size = b.size();
    row("bounds min", fmt::format("{:.6g} {:.6g} {:.6g}", b.lo.x(), b.lo.y(), b.lo.z()));
    row("bounds max", fmt::format("{:.6g} {:.6g} {:.6g}", b.hi.x(), b.hi.y(), b.hi.z()));
    row("size", fmt::format("{:.6g} {:.6g} {:.6g}", size.x(), size.y(), size.z()));
}

void inspect_surface(const std::string& path, double feature_angle) {
    SurfaceReadOptions read;
    read.allow_degenerate = true;  // counted below instead of refused
    const TriangleSurface s = read_surface(path, read);
    const SurfaceDiagnostics d = diagnose_surface(s);
    FeatureOptions fo;
    fo.angle_degrees = feature_angle;
    const FeatureCurves f = detect_sharp_features(s, fo);
    std::cout << fmt::format("surface {}\n", path);
    row("triangles", fmt::format("{}", d.triangles));
    row("points", fmt::format("{}", d.points));
    bounds_rows(d.bounds);
    row("edges", fmt::format("{}", d.edges));
    row("open (boundary) edges", fmt::format("{}", d.boundary_edges));
    row("non-manifold edges", fmt::format("{}", d.non_manifold_edges));
    row("inconsistently oriented edges", fmt::format("{}", d.inconsistent_edges));
    row("degenerate triangles", fmt::format("{}", d.degenerate_triangles));
    row("self-intersecting pairs", fmt::format("{}", d.self_intersections));
    row(fmt::format("crease chains ({:g} deg)", feature_angle), fmt::format("{}", f.chains.size()));
    row("corners", fmt::format("{}", f.corners.size()));
    row(fmt::format("edges beside them turning {:g}-{:g} deg", 0.5 * feature_angle, feature_angle),
        fmt::format("{}", f.half_turning_edges));
    if (!d.degenerate_ids.empty()) {
        std::string ids;
        for (int t : d.degenerate_ids) ids += fmt::format("{}{}", ids.empty() ? "" : " ", t);
        row("first degenerate triangles", ids);
    }
    std::cout << (d.watertight() ? "  watertight: yes (closed, manifold, oriented)\n"
                                 : "  watertight: no (the SDF will sign it by winding number "
                                   "if it has open edges)\n");
    if (f.scan_at(facet_noise_ratio))
        std::cout
            << "  faceted scan: yes (the edges beside its creases that turn by half the angle "
               "to it are half as many or more: tetmesh protects none of them)\n";
}

void inspect_points(const std::string& path) {
    const PointCloudDiagnostics d = diagnose_point_cloud(read_point_cloud(path));
    std::cout << fmt::format("point cloud {}\n", path);
    row("points (with normals)", fmt::format("{}", d.points));
    bounds_rows(d.bounds);
    row("mean spacing", fmt::format("{:.6g}", d.mean_spacing));
    row("largest gap", fmt::format("{:.6g}", d.largest_gap));
    row("duplicate points", fmt::format("{}", d.duplicates));
    row("normals against neighbours", fmt::format("{}", d.inconsistent_normals));
    std::cout << (d.inconsistent_normals == 0 && d.duplicates == 0
                      ? "  consistent: yes (normals agree with their neighbours)\n"
                      : "  consistent: no (flipped normals or sheets closer than the spacing "
                        "give a wrong sign nearby)\n");
}

void inspect_sections(const std::string& path) {
    const SectionDiagnostics d = diagnose_sections(read_sections(path));
    std::cout << fmt::format("cross-section stack {}\n", path);
    row("sections", fmt::format("{}", d.sections));
    row("polylines", fmt::format("{}", d.loops));
    row("points", fmt::format("{}", d.points));
    bounds_rows(d.bounds);
    row("section spacing min/max", fmt::format("{:.6g} {:.6g}", d.min_spacing, d.max_spacing));
    row("smallest polyline area", fmt::format("{:.6g}", d.smallest_loop_area));
    row("self-intersecting polylines", fmt::format("{}", d.self_intersecting_loops));
    row("crossing polyline pairs", fmt::format("{}", d.crossing_loops));
    std::cout << (d.self_intersecting_loops == 0 && d.crossing_loops == 0 &&
                          d.smallest_loop_area > 0
                      ? "  valid: yes (simple polylines, none crossing another)\n"
                      : "  valid: no (the even-odd rule gives no clean inside where polylines "
                        "cross)\n");
}

}  // namespace

void add_inspect_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string path, as = "auto";
        double feature_angle = 30;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand(
        "inspect", "print the diagnostics of a surface, point cloud or cross-section file");
    cmd->add_option("file", args->path,
                    "surface (.stl .obj .off .ply), point cloud with normals (.ply without "
                    "faces, .xyz) or cross-section stack (other extensions)")
        ->required();
    cmd->add_option("--as", args->as, "what the file holds, instead of guessing from its name")
        ->check(CLI::IsMember({"auto", "surface", "points", "sections"}))
        ->capture_default_str();
    cmd->add_option("--feature-angle", args->feature_angle,
                    "surfaces: crease threshold, dihedral turn in degrees")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 179.0));
    cmd->callback([args, &exit_code] {
        const GeometryFileKind kind = args->as == "surface"    ? GeometryFileKind::surface
                                      : args->as == "points"   ? GeometryFileKind::points
                                      : args->as == "sections" ? GeometryFileKind::sections
                                                               : geometry_file_kind(args->path);
        if (kind == GeometryFileKind::surface)
            inspect_surface(args->path, args->feature_angle);
        else if (kind == GeometryFileKind::points)
            inspect_points(args->path);
        else
            inspect_sections(args->path);
        exit_code = 0;
    });
}

}  // namespace hexmesh::cli
