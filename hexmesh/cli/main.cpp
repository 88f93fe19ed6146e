// hexmesh: structured hexahedral grids for CFD from implicit bodies (command-line entry).
#include <iostream>
#include <new>
#include <stdexcept>

#include "hexmesh/cli/commands.h"
#include "hexmesh/core/memory_limit.h"

int main(int argc, char** argv) {
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
        std::cerr << "hexmesh: error: " << e.what() << " (hexmesh --help lists the commands, "
                  << "hexmesh COMMAND --help their arguments)\n";
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "hexmesh: error: out of memory: the job needs more than this machine can give "
                     "(fewer cells, a coarser surface or a larger voxel size need less)\n";
        return 1;
    } catch (const std::length_error& e) {  // a std::vector asked for more than max_size()
        std::cerr << "hexmesh: error: out of memory: a size beyond any machine was asked for ("
                  << e.what() << ")\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "hexmesh: error: " << e.what() << "\n";
        return 1;
    }
    return exit_code;
}
