// `hexmesh tetmesh CASE.json -o OUT`: a sliver-free tetrahedral mesh of a case's body.
#include <fmt/format.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include "hexmesh/cli/commands.h"
#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/tet_mesh_case.h"
#include "io/case_file.h"
#include "io/report_page.h"
#include "io/volume_mesh_io.h"
#include "untangle/solver_options.h"

namespace hexmesh::cli {

void add_tetmesh_command(CLI::App& app, int& exit_code) {
    struct Args {
        std::string case_path, output, cgal_output;
        bool compare_cgal = false, no_report = false;
        double theta = tet_untangle_options().theta;
        int optimize_iterations = 20;
        Reweighting reweighting;
        double cap_degrees = 20, cgal_sliver_bound = 0, cgal_time_limit = 0, flip_degrees = 30;
        int flip_cycles = 3;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd =
        app.add_subcommand("tetmesh", "tetrahedral mesh of a case's body, slivers removed");
    cmd->add_option("case", args->case_path, "case file (JSON)")->required();
    cmd->add_option("-o,--output", args->output, "output mesh (.vtu .vtk)")->required();
    cmd->add_flag("--compare-cgal", args->compare_cgal,
                  "also run CGAL's perturb + exude on the same mesh and print both side by side");
    cmd->add_option("--cgal-output", args->cgal_output,
                    "write CGAL's perturbed and exuded mesh here")
        ->needs("--compare-cgal");
    cmd->add_flag("--no-report", args->no_report, "do not write NAME.report.html beside the mesh");
    cmd->add_option("--theta", args->theta, "weight of volume against shape, in (0, 1)")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--optimize-iterations", args->optimize_iterations,
                    "outer optimization iterations")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--reweight-rounds", args->reweighting.rounds,
                    "rounds that reweight each tet by its distortion to lift the worst")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--reweight-power", args->reweighting.power,
                    "exponent p of sum w phi^p the rounds aim at")
        ->check(CLI::Range(1.0, 8.0))
        ->capture_default_str();
    cmd->add_option("--cap-angle", args->cap_degrees,
                    "remove boundary caps (four points on the surface) below this dihedral angle "
                    "(degrees, 0: none)")
        ->check(CLI::Range(0.0, 60.0))
        ->capture_default_str();
    cmd->add_option("--flip-cycles", args->flip_cycles,
                    "cycles of edge removals and 2-3 flips, each followed by the optimization "
                    "again (0: none)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--flip-angle", args->flip_degrees,
                    "flip around the tets below this dihedral angle (degrees)")
        ->check(CLI::Range(0.0, 70.0))
        ->capture_default_str();
    cmd->add_option("--cgal-sliver-bound", args->cgal_sliver_bound,
                    "--compare-cgal: smallest dihedral angle CGAL's perturber aims at (degrees; 0: "
                    "its default, 12)")
        ->check(CLI::Range(0.0, 60.0))
        ->capture_default_str();
    cmd->add_option("--cgal-time-limit", args->cgal_time_limit,
                    "--compare-cgal: seconds for CGAL's perturb and for its exude (0: no limit)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->callback([args, &exit_code] {
        const Case c = read_case(args->case_path);
        check_volume_mesh_output(args->output);
        if (!args->cgal_output.empty()) {
            check_volume_mesh_output(args->cgal_output);
            if (std::filesystem::weakly_canonical(args->cgal_output) ==
                std::filesystem::weakly_canonical(args->output))
                throw std::invalid_argument("--cgal-output must differ from -o (" + args->output +
                                            ")");
        }
        std::cout << fmt::format("hexmesh tetmesh {}\n", args->case_path);
        TetCaseOptions options;
        options.compare_cgal = args->compare_cgal;
        options.reweighting = args->reweighting;
        options.cap_degrees = args->cap_degrees;
        options.cgal_sliver_bound = args->cgal_sliver_bound;
        options.flip_cycles = args->flip_cycles;
        options.flip_degrees = args->flip_degrees;
        options.cgal_time_limit = args->cgal_time_limit;
        options.untangle.theta = args->theta;
        options.untangle.max_optimize_iterations = args->optimize_iterations;
        options.untangle.untangle_solver.method = untangle::method_from_name(c.solver.untangle);
        options.untangle.optimize_solver.method = untangle::method_from_name(c.solver.optimize);
        options.untangle.max_untangle_iterations = c.solver.max_iterations;
        options.untangle.log = &std::cout;
        const TetCaseResult r = run_tet_case(c, options, std::cout);
        std::cout << "\n"
                  << untangle::format_untangle_summary(r.optimization.solve) << "\n"
                  << format_tet_comparison(r);
        if (r.optimized.inverted > 0) {
            std::cout << fmt::format("\n{} inverted tets remain: nothing written\n",
                                     r.optimized.inverted);
            exit_code = 3;
            return;
        }
        write_volume_mesh(VolumeMesh{r.mesh.points, {}, r.mesh.tets, {}}, args->output);
        if (!args->cgal_output.empty()) {
            const TetMesh& m = r.generation.cgal_optimized->mesh;
            try {
                write_volume_mesh(VolumeMesh{m.points, {}, m.tets, {}}, args->cgal_output);
            } catch (...) {
                std::filesystem::remove(args->output);  // both or neither
                throw;
            }
        }
        std::cout << "\nwritten: " << args->output << "\n";
        if (!args->cgal_output.empty()) std::cout << "written: " << args->cgal_output << "\n";
        if (!args->no_report) {
            ReportPage page =
                tet_mesh_report_page("hexmesh tetmesh " + args->case_path, r.mesh, r.optimized);
            page.settings_json = case_to_json(c);
            page.peak_memory_bytes = peak_memory();
            std::cout << "written: " << write_report_beside(args->output, page) << "\n";
        }
        if (r.optimized.slivers > 0) {
            std::cout << fmt::format(
                "\nwarning: {} slivers remain (a dihedral angle under {:.3g} degrees; the smallest "
                "{:.3g}), the mesh is written but a solver may reject them\n",
                r.optimized.slivers, r.optimized.sliver_degrees, r.optimized.min_dihedral);
            exit_code = 3;
            return;
        }
        exit_code = 0;
    });
}

}  // namespace hexmesh::cli
