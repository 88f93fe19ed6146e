// `hexmesh untangle IN -o OUT`: makes a tangled hex or tet mesh valid, then optimizes it.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "hexmesh/cli/commands.h"
#include "hexmesh/pipeline/untangle_mesh.h"
#include "hexmesh/quality/grid_report.h"
#include "hexmesh/quality/mesh_quality.h"
#include "io/input_error.h"
#include "io/volume_mesh_io.h"

namespace hexmesh::cli {
namespace {

struct Args {
    std::string input, output, solver = "newton-cg", optimize_solver = "block-diagonal";
    std::string preconditioner = "block-jacobi", boundary = "fixed", surface;
    // The untangler's own weights (untangle/untangle.h).
    double theta = untangle::UntangleOptions().theta,
           untangle_theta = untangle::UntangleOptions().untangle_theta, feature_angle = 30;
    int max_iterations = 200, optimize_iterations = 2;
    bool matrix_free = false, keep_invalid = false, no_report = false;
    std::string target = "uniform";
};

std::string invalid_name(const std::string& path) {
    std::filesystem::path p(path);
    return (p.parent_path() / (p.stem().string() + "_invalid" + p.extension().string())).string();
}

void print_quality(const QualityReport& before, const QualityReport& after) {
    GridReport b, a;
    b.quality = before;
    a.quality = after;
    std::cout << "\nquality before\n"
              << format_quality_table(b) << "quality after\n"
              << format_quality_table(a);
}

// The options the mesh was untangled with, for its report page.
std::string settings_json(const Args& a) {
    nlohmann::ordered_json j;
    j["input"] = a.input;
    j["boundary"] = a.boundary;
    if (!a.surface.empty()) j["surface"] = a.surface;
    j["solver"] = a.solver;
    j["optimize_solver"] = a.optimize_solver;
    j["preconditioner"] = a.preconditioner;
    j["matrix_free"] = a.matrix_free;
    j["theta"] = a.theta;
    j["untangle_theta"] = a.untangle_theta;
    j["max_iterations"] = a.max_iterations;
    j["optimize_iterations"] = a.optimize_iterations;
    j["feature_angle_deg"] = a.feature_angle;
    j["target"] = a.target;
    return j.dump(1);
}

int run(const Args& args) {
    UntangleMeshOptions options;
    options.untangle.untangle_solver.method = untangle::method_from_name(args.solver);
    for (untangle::SolverOptions* solver :
         {&options.untangle.untangle_solver, &options.untangle.optimize_solver}) {
        solver->preconditioner = untangle::preconditioner_from_name(args.preconditioner);
        solver->matrix_free = args.matrix_free;
    }
    options.untangle.optimize_solver.method = untangle::method_from_name(args.optimize_solver);
    options.untangle.theta = args.theta;
    options.untangle.untangle_theta = args.untangle_theta;
    options.untangle.max_untangle_iterations = args.max_iterations;
    options.untangle.max_optimize_iterations = args.optimize_iterations;
    options.untangle.log = &std::cout;
    options.boundary = args.boundary == "slip" ? BoundaryMode::slip : BoundaryMode::fixed;
    options.feature_angle_degrees = args.feature_angle;
    options.uniform_target = args.target == "uniform";
    if (!args.surface.empty()) {
        if (options.boundary != BoundaryMode::slip)
            throw std::invalid_argument("--surface needs --boundary slip");
        slip_on_file(args.surface, options);
    }
    check_volume_mesh_output(args.output);
    VolumeMesh mesh = read_volume_mesh(args.input);
    std::cout << fmt::format("hexmesh untangle {}: {} hexes, {} tets, {} points, boundary {}\n",
                             args.input, mesh.num_hexes(), mesh.num_tets(), mesh.points.size(),
                             args.boundary);

    const UntangleMeshResult r =
        naming_file(args.input, [&] { return untangle_volume_mesh(mesh, options); });
    std::cout << fmt::format("vertices: {} slip, {} on creases, {} fixed\n", r.slip_vertices,
                             r.feature_vertices, r.fixed_vertices);
    if (!r.blocked.empty()) std::cout << describe_blocked(r.blocked);
    std::cout << "\n" << untangle::format_untangle_summary(r.solve);
    if (r.hex_before && r.hex_after) print_quality(*r.hex_before, *r.hex_after);
    if (options.boundary == BoundaryMode::slip)
        std::cout << fmt::format("  {:<30}{:>14.3g}\n", "max distance to the surface",
                                 r.max_surface_distance);

    const bool valid = r.solve.inverted_after == 0;
    if (!valid && !args.keep_invalid) {
        std::cout << fmt::format(
            "\nnot untangled: {} inverted elements remain; nothing written "
            "(--keep-invalid writes the best mesh reached as {})\n",
            r.solve.inverted_after, invalid_name(args.output));
        return 3;
    }
    const std::string out = valid ? args.output : invalid_name(args.output);
    const std::string settings = settings_json(args);
    const std::vector<std::string> written = write_untangled_mesh(
        mesh, r, out, "hexmesh untangle " + args.input, args.no_report ? nullptr : &settings);
    std::cout << "\n";
    for (const std::string& f : written) std::cout << "written: " << f << "\n";
    return valid ? 0 : 3;
}

}  // namespace

void add_untangle_command(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<Args>();
    CLI::App* cmd =
        app.add_subcommand("untangle", "make a tangled hex or tet mesh valid, then optimize it");
    cmd->add_option("mesh", args->input, "input mesh (.vtk .vtu .mesh)")->required();
    cmd->add_option("-o,--output", args->output, "output mesh (.vtu .vtk .mesh)")->required();
    cmd->add_option("--solver", args->solver,
                    "untangling method: explicit, block-diagonal, "
                    "coordinate-split, newton-cg, lbfgs")
        ->capture_default_str();
    cmd->add_option("--optimize-solver", args->optimize_solver, "method once the mesh is valid")
        ->capture_default_str();
    cmd->add_option("--preconditioner", args->preconditioner,
                    "newton-cg, both phases: none, jacobi, block-jacobi, incomplete-cholesky")
        ->capture_default_str();
    cmd->add_flag("--matrix-free", args->matrix_free,
                  "newton-cg, both phases: Hessian products without a matrix");
    cmd->add_option("--boundary", args->boundary, "boundary vertices: fixed or slip")
        ->check(CLI::IsMember({"fixed", "slip"}))
        ->capture_default_str();
    cmd->add_option(
        "--surface", args->surface,
        "surface to slip on (.stl .obj .off .ply), or a case file (.json) whose geometry it is");
    cmd->add_option("--feature-angle", args->feature_angle,
                    "crease angle of the slip surface (degrees)")
        ->capture_default_str();
    cmd->add_option("--target", args->target, "target cell size: cell (each cell's own) or uniform")
        ->check(CLI::IsMember({"cell", "uniform"}))
        ->capture_default_str();
    cmd->add_option("--theta", args->theta,
                    "weight of volume against shape while optimizing, in (0, 1)")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--untangle-theta", args->untangle_theta, "the same weight while untangling")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--max-iter", args->max_iterations, "outer untangling iterations")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_option("--optimize-iterations", args->optimize_iterations,
                    "outer optimization iterations once valid (0: untangle only)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_flag("--keep-invalid", args->keep_invalid,
                  "write a mesh that stays tangled as NAME_invalid.EXT");
    cmd->add_flag("--no-report", args->no_report, "do not write NAME.report.html beside the mesh");
    cmd->callback([args, &exit_code] { exit_code = run(*args); });
}

}  // namespace hexmesh::cli
