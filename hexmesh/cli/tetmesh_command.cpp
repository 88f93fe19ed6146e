// `hexmesh tetmesh CASE.json -o OUT`: a sliver-free tetrahedral mesh of a case's body.
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "hexmesh/cli/commands.h"
#include "hexmesh/pipeline/job.h"
#include "hexmesh/pipeline/tet_mesh_case.h"
#include "io/case_file.h"
#include "untangle/solver_options.h"

namespace hexmesh::cli {

namespace {

struct Args {
    std::string case_path, output, cgal_output;
    bool compare_cgal = false, no_report = false;
    double theta = tet_untangle_options().theta;
    int optimize_iterations = 20;
    Reweighting reweighting;
    double cap_degrees = 20, cgal_sliver_bound = 0, cgal_time_limit = 0, flip_degrees = 30;
    double raise_degrees = 15;
    int flip_cycles = 3;
};

// The optimizer's options on the command line.
void add_optimizer_options(CLI::App* cmd, Args& args) {
    cmd->add_option("--theta", args.theta, "weight of volume against shape, in (0, 1)")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--optimize-iterations", args.optimize_iterations,
                    "outer optimization iterations")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--reweight-rounds", args.reweighting.rounds,
                    "rounds that reweight each tet by its distortion to lift the worst")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--reweight-power", args.reweighting.power,
                    "exponent p of sum w phi^p the rounds aim at")
        ->check(CLI::Range(1.0, 8.0))
        ->capture_default_str();
    cmd->add_option("--cap-angle", args.cap_degrees,
                    "remove boundary caps (four points on the surface) below this dihedral angle "
                    "(degrees, 0: none)")
        ->check(CLI::Range(0.0, 60.0))
        ->capture_default_str();
    cmd->add_option("--flip-cycles", args.flip_cycles,
                    "cycles of edge removals and 2-3 flips, each followed by the optimization "
                    "again (0: none)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--flip-angle", args.flip_degrees,
                    "flip around the tets below this dihedral angle (degrees)")
        ->check(CLI::Range(0.0, 70.0))
        ->capture_default_str();
    cmd->add_option("--raise-angle", args.raise_degrees,
                    "last, move the points of the tets below this dihedral angle to raise it, and "
                    "insert points in those with four boundary points (degrees, 0: none)")
        ->check(CLI::Range(0.0, 30.0))
        ->capture_default_str();
}

// The comparison with CGAL's sliver removal on the command line.
void add_cgal_options(CLI::App* cmd, Args& args) {
    cmd->add_flag("--compare-cgal", args.compare_cgal,
                  "also run CGAL's perturb + exude on the same mesh and print both side by side");
    cmd->add_option("--cgal-output", args.cgal_output,
                    "write CGAL's perturbed and exuded mesh here")
        ->needs("--compare-cgal");
    cmd->add_option("--cgal-sliver-bound", args.cgal_sliver_bound,
                    "--compare-cgal: smallest dihedral angle CGAL's perturber aims at (degrees; 0: "
                    "its default, 12)")
        ->check(CLI::Range(0.0, 60.0))
        ->capture_default_str();
    cmd->add_option("--cgal-time-limit", args.cgal_time_limit,
                    "--compare-cgal: seconds for CGAL's perturb and for its exude (0: no limit)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
}

// The job's options: the command line's, and the case's solver block for the rest.
TetCaseOptions tet_case_options(const Args& args, const Case& c) {
    TetCaseOptions options;
    options.compare_cgal = args.compare_cgal;
    options.reweighting = args.reweighting;
    options.cap_degrees = args.cap_degrees;
    options.cgal_sliver_bound = args.cgal_sliver_bound;
    options.flip_cycles = args.flip_cycles;
    options.flip_degrees = args.flip_degrees;
    options.raise_degrees = args.raise_degrees;
    options.cgal_time_limit = args.cgal_time_limit;
    options.untangle = case_solver_options(c.solver, &std::cout);
    options.untangle.theta = args.theta;
    options.untangle.max_optimize_iterations = args.optimize_iterations;
    return options;
}

// The job, its table and files; the exit code: 3 when tets are inverted (nothing written) or
// slivers remain (written, with a warning).
int run_tetmesh(const Args& args) {
    const Case c = read_case(args.case_path);
    check_tet_outputs(args.output, args.cgal_output);
    std::cout << fmt::format("hexmesh tetmesh {}\n", args.case_path);
    const TetCaseResult r = run_tet_case(c, tet_case_options(args, c), std::cout);
    std::cout << "\n"
              << untangle::format_untangle_summary(r.optimization.solve) << "\n"
              << format_tet_comparison(r);
    if (r.optimized.inverted > 0) {
        std::cout << fmt::format("\n{} inverted tets remain: nothing written\n",
                                 r.optimized.inverted);
        return 3;
    }
    const std::vector<std::string> written = write_tet_case(
        r, c, args.output, args.cgal_output, !args.no_report, "hexmesh tetmesh " + args.case_path);
    std::cout << "\n";
    for (const std::string& f : written) std::cout << "written: " << f << "\n";
    if (r.optimized.slivers > 0) {
        std::cout << fmt::format(
            "\nwarning: {} slivers remain (a dihedral angle under {:.3g} degrees; the smallest "
            "{:.3g}), the mesh is written but a solver may reject them\n",
            r.optimized.slivers, r.optimized.sliver_degrees, r.optimized.min_dihedral);
        return 3;
    }
    return 0;
}

}  // namespace

void add_tetmesh_command(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<Args>();
    CLI::App* cmd =
        app.add_subcommand("tetmesh", "tetrahedral mesh of a case's body, slivers removed");
    cmd->add_option("case", args->case_path, "case file (JSON)")->required();
    cmd->add_option("-o,--output", args->output, "output mesh (.vtu .vtk)")->required();
    cmd->add_flag("--no-report", args->no_report, "do not write NAME.report.html beside the mesh");
    add_cgal_options(cmd, *args);
    add_optimizer_options(cmd, *args);
    cmd->callback([args, &exit_code] { exit_code = run_tetmesh(*args); });
}

}  // namespace hexmesh::cli
