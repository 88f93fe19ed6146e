// Discretization uncertainty from three grid levels: the GCI procedure of Celik et al. (2008).
#pragma once

#include <string>

namespace hexmesh {

// Results of one quantity on three grids, fine (1), medium (2) and coarse (3), and the
// refinement ratios r21 = h2 / h1, r32 = h3 / h2 (> 1; 2 for a hexmesh family).
struct GridConvergenceInput {
    double phi1 = 0, phi2 = 0, phi3 = 0;
    double r21 = 2, r32 = 2;
};

// The five numbers of Celik, Ghia, Roache, Freitas, Coleman, Raad, "Procedure for
// Estimation and Reporting of Uncertainty Due to Discretization in CFD Applications",
// J. Fluids Eng. 130 (2008) 078001, section 2 (relative errors as fractions, not percent).
struct GridConvergence {
    double order = 0;                        // observed (apparent) order p
    double extrapolated = 0;                 // phi_ext^21 = (r21^p phi1 - phi2) / (r21^p - 1)
    double relative_error = 0;               // e_a^21 = |(phi1 - phi2) / phi1|
    double extrapolated_relative_error = 0;  // e_ext^21 = |(phi_ext^21 - phi1) / phi_ext^21|
    double gci_fine = 0;                     // GCI_fine^21 = 1.25 e_a^21 / (r21^p - 1)
    bool oscillatory = false;                // s = sign((phi3 - phi2) / (phi2 - phi1)) < 0
    int iterations = 0;                      // fixed-point iterations for p (0 when r21 == r32)
};

// With eps32 = phi3 - phi2, eps21 = phi2 - phi1, s = sign(eps32 / eps21):
// p = |ln|eps32 / eps21| + q(p)| / ln r21, q(p) = ln((r21^p - s) / (r32^p - s)), solved by
// fixed-point iteration from q = 0 (q = 0 exactly when r21 == r32). Throws
// std::invalid_argument when a ratio is not > 1, a value is not finite, eps21 or eps32 is
// zero (no convergence to measure), phi1 or phi_ext is zero (relative errors undefined), or
// the iteration does not converge in 200 steps.
GridConvergence grid_convergence(const GridConvergenceInput& input);

// Where the observed order p must lie, in multiples of the scheme's formal order, for the three
// grids to count as in the asymptotic range (p near the formal order; far from it, the error
// is not yet the leading term of its expansion, and phi_ext and the GCI do not bound it).
struct OrderRange {
    double low = 0.5;  // p below half the formal order: the error falls too slowly
    double high = 2;   // above twice: too fast (differences of round-off, or of cancelling terms)
};

// One warning line about the observed order p against `formal_order` (> 0), naming what it
// means, or an empty string when low * formal <= p <= high * formal. A p that is not finite
// is warned about too.
std::string order_warning(double observed_order, double formal_order, const OrderRange& range = {});

}  // namespace hexmesh
