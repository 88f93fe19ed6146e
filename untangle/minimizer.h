// Descent at a fixed eps: direction by the chosen method, step by dichotomy on F(V(x + tau d)).
#pragma once

#include <deque>
#include <functional>
#include <vector>

#include "untangle/assembly.h"
#include "untangle/solver_options.h"

namespace hexmesh::untangle {

struct MinimizeOutcome {
    double energy = 0;
    int steps = 0;              // accepted steps
    int linear_iterations = 0;  // CG iterations over all steps
    int trials = 0;             // energy evaluations of the line searches (tau = 1, 1/2, ...)
};

// Holds what lives across steps: the Hessian pattern and the L-BFGS history.
class Minimizer {
  public:
    Minimizer(const Problem& problem, const Assembly& assembly, const SolverOptions& options);

    // Up to max_steps descent steps on F at fixed p, stopping when a step lowers F by less
    // than tolerance * |F|, or when the line search finds no decrease. x is updated in place
    // and stays on its constraints (V applied after every step).
    // `done`, when given, is asked after every accepted step and ends the solve early.
    MinimizeOutcome minimize(std::vector<Vec3>& x, const EnergyParams& p, int max_steps,
                             double tolerance,
                             const std::function<bool(const std::vector<Vec3>&)>& done = {});

  private:
    // Direction d for the current x (in 3D, inside the allowed bases); returns F(x).
    double direction(const std::vector<Vec3>& x, const EnergyParams& p, std::vector<Vec3>& d,
                     int& linear_iterations);
    double newton_direction(const std::vector<Vec3>& x, const EnergyParams& p,
                            const std::vector<Mat3>& basis, std::vector<Vec3>& d, int& iterations);
    double lbfgs_direction(const std::vector<Vec3>& x, const EnergyParams& p,
                           const std::vector<Mat3>& basis, std::vector<Vec3>& d);

    const Problem& problem_;
    const Assembly& assembly_;
    SolverOptions options_;
    BlockMatrix hessian_;
    std::deque<std::pair<std::vector<Vec3>, std::vector<Vec3>>> history_;  // (s, y) pairs
    std::vector<Vec3> last_x_, last_gradient_;
};

}  // namespace hexmesh::untangle
