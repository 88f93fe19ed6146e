// The subcommands of the hexmesh executable; each registers itself on the CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

namespace hexmesh::cli {

// Each add_*_command adds one subcommand to `app`. Its callback runs the job when the
// subcommand is chosen and stores the process exit code in `exit_code`; errors are thrown
// (std::exception) and reported once by main().
void add_run_command(CLI::App& app, int& exit_code);
void add_quality_command(CLI::App& app, int& exit_code);
void add_report_command(CLI::App& app, int& exit_code);
void add_compare_command(CLI::App& app, int& exit_code);
void add_inspect_command(CLI::App& app, int& exit_code);
void add_sdf_command(CLI::App& app, int& exit_code);
void add_export_command(CLI::App& app, int& exit_code);
void add_untangle_command(CLI::App& app, int& exit_code);
void add_refine_command(CLI::App& app, int& exit_code);
void add_gci_command(CLI::App& app, int& exit_code);
void add_tetmesh_command(CLI::App& app, int& exit_code);

}  // namespace hexmesh::cli
