// `hexmesh gci F1 F2 F3 [--ratio R] [--ratio32 R] [--order P]`: discretization uncertainty of
// a result computed on the fine, medium and coarse grids of a family (Celik et al. 2008), with
// a warning line (stderr) for a ratio assumed and for an observed order far from the formal one.
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "hexmesh/cli/commands.h"
#include "hexmesh/pipeline/grid_convergence.h"
#include "io/case_file.h"

namespace hexmesh::cli {

void add_gci_command(CLI::App& app, int& exit_code) {
    struct Args {
        double phi1 = 0, phi2 = 0, phi3 = 0, ratio = 2, order = 2;
        std::optional<double> ratio32;
        bool allow_oscillatory = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand(
        "gci", "grid convergence index of a result on the fine, medium and coarse grids");
    cmd->add_option("F1", args->phi1, "result on the fine grid")->required();
    cmd->add_option("F2", args->phi2, "result on the medium grid")->required();
    cmd->add_option("F3", args->phi3, "result on the coarse grid")->required();
    CLI::Option* ratio =
        cmd->add_option("--ratio", args->ratio, "refinement ratio h2/h1 (and h3/h2)")
            ->capture_default_str();
    cmd->add_option("--ratio32", args->ratio32, "refinement ratio h3/h2 (default: --ratio)");
    cmd->add_flag("--allow-oscillatory", args->allow_oscillatory,
                  "accept values that go up and down (oscillatory convergence, s = -1)");
    cmd->add_option("--order", args->order,
                    "formal order of the scheme: a warning when the observed order is below half "
                    "of it or above twice")
        ->capture_default_str();
    cmd->callback([args, ratio, &exit_code] {
        GridConvergenceInput in;
        in.phi1 = args->phi1, in.phi2 = args->phi2, in.phi3 = args->phi3;
        in.r21 = args->ratio;
        in.r32 = args->ratio32.value_or(args->ratio);
        // Every number as given: a NaN or a ratio <= 1 is refused, never replaced by a default.
        const std::pair<const char*, double> given[] = {{"F1", in.phi1},
                                                        {"F2", in.phi2},
                                                        {"F3", in.phi3},
                                                        {"--ratio", in.r21},
                                                        {"--ratio32", in.r32}};
        for (const auto& [name, value] : given)
            if (!std::isfinite(value))
                throw InputError(
                    fmt::format("gci: {} is {}: expected a finite number", name, value));
        for (const auto& [name, value] : {given[3], given[4]})
            if (!(value > 1))
                throw InputError(
                    fmt::format("gci: {} is {}: a refinement ratio must be > 1", name, value));
        if (!(args->order > 0) || !std::isfinite(args->order))
            throw InputError(
                fmt::format("gci: --order is {}: expected the scheme's formal order, a number > 0",
                            args->order));
        GridConvergence g;
        try {
            g = grid_convergence(in);
        } catch (const std::invalid_argument& e) {
            throw InputError(fmt::format("gci: {}", e.what()));
        }
        if (g.oscillatory && !args->allow_oscillatory)
            throw InputError(fmt::format(
                "gci: the values are not monotone (F1 = {}, F2 = {}, F3 = {}): oscillatory "
                "convergence; pass --allow-oscillatory to estimate it anyway",
                in.phi1, in.phi2, in.phi3));
        std::cout << fmt::format(
            "  refinement ratios r21, r32          {:.6g} {:.6g}\n"
            "  convergence                         {}\n"
            "  observed order p                    {:.6g}\n"
            "  extrapolated value phi_ext^21       {:.6g}\n"
            "  approximate relative error e_a^21   {:.4g} %\n"
            "  extrapolated rel. error e_ext^21    {:.4g} %\n"
            "  GCI_fine^21                         {:.4g} %\n",
            in.r21, in.r32, g.oscillatory ? "oscillatory" : "monotone", g.order, g.extrapolated,
            100 * g.relative_error, 100 * g.extrapolated_relative_error, 100 * g.gci_fine);
        if (ratio->count() == 0)
            std::cerr << fmt::format(
                "hexmesh: warning: gci: no --ratio given: assumed refinement ratio h2/h1 = {:g}{} "
                "(a hexmesh family: every cell split in two per direction); give --ratio for grids "
                "refined otherwise\n",
                in.r21, args->ratio32 ? "" : fmt::format(" and h3/h2 = {:g}", in.r32));
        const std::string order = order_warning(g.order, args->order);
        if (!order.empty()) std::cerr << "hexmesh: warning: gci: " << order << "\n";
        exit_code = 0;
    });
}

}  // namespace hexmesh::cli
