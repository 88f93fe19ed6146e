// hexmesh: structured hexahedral grids for CFD from implicit bodies (command-line entry).
#include <iostream>
#include <new>
#include <optional>
#include <stdexcept>

#include "hexmesh/cli/commands.h"
#include "hexmesh/core/memory_limit.h"
#include "hexmesh/pipeline/ranks.h"
#include "io/input_error.h"

namespace {

// Under mpirun every process meets the same bad input: rank 0 says it once; other errors are
// the rank's own and each says which rank met it.
void print_error(const std::string& message, bool same_on_every_rank) {
    const int rank = hexmesh::ranks::rank();
    if (rank == 0)
        std::cerr << "hexmesh: error: " << message << "\n";
    else if (!same_on_every_rank)
        std::cerr << "hexmesh: error: process " << rank << ": " << message << "\n";
}

}  // namespace

int main(int argc, char** argv) {
    std::optional<hexmesh::ranks::Session> session;
    try {
        session.emplace(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "hexmesh: error: " << e.what() << "\n";
        return 1;
    }
    CLI::App app{"hexmesh: structured hexahedral grids for CFD from implicit bodies"};
    app.require_subcommand(1);
    double max_memory_gb = 0;
    app.add_option("--max-memory", max_memory_gb,
                   "largest memory a job may ask for, in GB (default: half of this machine's); "
                   "before the command")
        ->check(CLI::PositiveNumber)
        ->each([](const std::string& gb) { hexmesh::set_memory_limit(std::stod(gb) * 1e9); });
    int exit_code = 0;
    hexmesh::cli::add_run_command(app, exit_code);
    hexmesh::cli::add_quality_command(app, exit_code);
    hexmesh::cli::add_report_command(app, exit_code);
    hexmesh::cli::add_compare_command(app, exit_code);
    hexmesh::cli::add_inspect_command(app, exit_code);
    hexmesh::cli::add_sdf_command(app, exit_code);
    hexmesh::cli::add_export_command(app, exit_code);
    hexmesh::cli::add_untangle_command(app, exit_code);
    hexmesh::cli::add_refine_command(app, exit_code);
    hexmesh::cli::add_gci_command(app, exit_code);
    hexmesh::cli::add_tetmesh_command(app, exit_code);
    // Only refine shares its work between processes; the others would each do all of it.
    app.parse_complete_callback([&app] {
        if (hexmesh::ranks::size() > 1 && !app.got_subcommand("refine"))
            throw hexmesh::InputError(
                "only `refine` runs on several processes (mpirun -np N hexmesh refine ...); run "
                "this command without mpirun");
    });
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {  // --help
        return app.exit(e);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // A wrong argument is a refusal like any other: one line, exit code 1.
        print_error(std::string(e.what()) +
                        " (hexmesh --help lists the commands, hexmesh COMMAND --help their "
                        "arguments)",
                    true);
        return 1;
    } catch (const std::bad_alloc&) {
        print_error(
            "out of memory: the job needs more than this machine can give (fewer cells, a "
            "coarser surface or a larger voxel size need less)",
            false);
        return 1;
    } catch (const std::length_error& e) {  // a std::vector asked for more than max_size()
        print_error(std::string("out of memory: a size beyond any machine was asked for (") +
                        e.what() + ")",
                    false);
        return 1;
    } catch (const hexmesh::InputError& e) {
        print_error(e.what(), true);
        return 1;
    } catch (const hexmesh::ranks::EveryRankError& e) {
        print_error(e.what(), true);
        return 1;
    } catch (const std::exception& e) {
        print_error(e.what(), false);
        return 1;
    }
    return exit_code;
}
