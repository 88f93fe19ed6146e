#include "hexmesh/pipeline/grid_convergence.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace hexmesh {

GridConvergence grid_convergence(const GridConvergenceInput& in) {
    if (!(in.r21 > 1) || !(in.r32 > 1) || !std::isfinite(in.r21) || !std::isfinite(in.r32))
        throw std::invalid_argument(fmt::format(
            "refinement ratios must be finite and > 1, got r21 = {}, r32 = {}", in.r21, in.r32));
    if (!std::isfinite(in.phi1) || !std::isfinite(in.phi2) || !std::isfinite(in.phi3))
        throw std::invalid_argument("the three values must be finite numbers");
    const double eps21 = in.phi2 - in.phi1, eps32 = in.phi3 - in.phi2;
    if (eps21 == 0 || eps32 == 0)
        throw std::invalid_argument(fmt::format(
            "the values must differ between levels (phi2 - phi1 = {}, phi3 - phi2 = {}): no "
            "convergence to measure",
            eps21, eps32));
    if (in.phi1 == 0) throw std::invalid_argument("phi1 = 0: the relative errors are undefined");

    GridConvergence g;
    const double s = eps32 / eps21 > 0 ? 1.0 : -1.0;
    g.oscillatory = s < 0;
    const double log_ratio = std::log(std::abs(eps32 / eps21));
    const double ln_r21 = std::log(in.r21);
    const auto q = [&](double p) {
        return std::log((std::pow(in.r21, p) - s) / (std::pow(in.r32, p) - s));
    };
    double p = std::abs(log_ratio) / ln_r21;  // q = 0: exact when r21 == r32
    if (in.r21 != in.r32) {
        bool converged = false;
        for (g.iterations = 1; g.iterations <= 200 && !converged; ++g.iterations) {
            const double next = std::abs(log_ratio + q(p)) / ln_r21;
            if (!std::isfinite(next)) break;
            converged = std::abs(next - p) <= 1e-12 * std::max(1.0, std::abs(next));
            p = next;
        }
        --g.iterations;
        if (!converged)
            throw std::invalid_argument(fmt::format(
                "the observed order does not converge (last p = {}): the three values are not "
                "in the asymptotic range",
                p));
    }
    g.order = p;
    const double rp = std::pow(in.r21, p);
    if (!(rp > 1))
        throw std::invalid_argument(fmt::format("observed order p = {}: r21^p - 1 is zero", p));
    g.extrapolated = (rp * in.phi1 - in.phi2) / (rp - 1);
    if (g.extrapolated == 0)
        throw std::invalid_argument("phi_ext = 0: the extrapolated relative error is undefined");
    g.relative_error = std::abs((in.phi1 - in.phi2) / in.phi1);
    g.extrapolated_relative_error = std::abs((g.extrapolated - in.phi1) / g.extrapolated);
    g.gci_fine = 1.25 * g.relative_error / (rp - 1);
    return g;
}

std::string order_warning(double p, double formal, const OrderRange& range) {
    if (!std::isfinite(p))
        return fmt::format(
            "observed order p = {} is not a finite number: the three grids are not in the "
            "asymptotic range; phi_ext and GCI mean nothing",
            p);
    const bool low = p<range.low * formal, high = p> range.high * formal;
    if (!low && !high) return "";
    const double bound = (low ? range.low : range.high) * formal;
    return fmt::format(
        "observed order p = {:.3g} is {} {:g} times the formal order {:g} (p {} {:g}): the three "
        "grids are not in the asymptotic range, so phi_ext and GCI are not reliable (refine "
        "further, or check that the iterative error is converged)",
        p, low ? "below" : "above", low ? range.low : range.high, formal, low ? "<" : ">", bound);
}

}  // namespace hexmesh
