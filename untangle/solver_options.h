// The descent methods of the untangler and their options (docs/architecture.md#solvers).
#pragma once

#include <string>

namespace hexmesh::untangle {

// explicit: gradient steps; block_diagonal: per-vertex 3x3 (2x2 slip, 1x1 edge) Newton
// blocks; coordinate_split: only same-coordinate couplings, 3 scalar SPD systems by CG
// (the paper's "implicit" method); newton_cg: full PSD block Hessian by preconditioned CG;
// lbfgs: quasi-Newton on the tangential gradient.
enum class Method { explicit_gradient, block_diagonal, coordinate_split, newton_cg, lbfgs };
enum class Preconditioner { none, jacobi, block_jacobi, incomplete_cholesky };

struct SolverOptions {
    Method method = Method::newton_cg;
    Preconditioner preconditioner = Preconditioner::block_jacobi;
    bool matrix_free = false;    // newton_cg: Hessian products element by element, no matrix
    double cg_tolerance = 1e-2;  // relative residual: a loose solve is enough
    int cg_max_iterations = 200;
    int lbfgs_history = 8;
    int max_halvings = 40;  // dichotomy line search: tau = 1, 1/2, 1/4, ...
};

// Names as written in case files and on the command line ("newton-cg", "block-jacobi", ...).
// Throw std::invalid_argument listing the valid names for an unknown one.
Method method_from_name(const std::string& name);
Preconditioner preconditioner_from_name(const std::string& name);
std::string to_string(Method method);
std::string to_string(Preconditioner preconditioner);

}  // namespace hexmesh::untangle
