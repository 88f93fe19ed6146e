#include "untangle/solver_options.h"

#include <array>
#include <stdexcept>
#include <utility>

namespace hexmesh::untangle {
namespace {

constexpr std::array<std::pair<Method, const char*>, 5> methods = {{
    {Method::explicit_gradient, "explicit"},
    {Method::block_diagonal, "block-diagonal"},
    {Method::coordinate_split, "coordinate-split"},
    {Method::newton_cg, "newton-cg"},
    {Method::lbfgs, "lbfgs"},
}};
constexpr std::array<std::pair<Preconditioner, const char*>, 4> preconditioners = {{
    {Preconditioner::none, "none"},
    {Preconditioner::jacobi, "jacobi"},
    {Preconditioner::block_jacobi, "block-jacobi"},
    {Preconditioner::incomplete_cholesky, "incomplete-cholesky"},
}};

template <class Table>
auto from_name(const Table& table, const std::string& name, const char* what) {
    std::string valid;
    for (const auto& [value, text] : table) {
        if (name == text) return value;
        valid += (valid.empty() ? "" : ", ") + std::string(text);
    }
    throw std::invalid_argument("unknown " + std::string(what) + " '" + name +
                                "' (valid: " + valid + ")");
}

template <class Table, class Value>
std::string to_name(const Table& table, Value v) {
    for (const auto& [value, text] : table)
        if (value == v) return text;
    return "?";
}

}  // namespace

Method method_from_name(const std::string& name) {
    return from_name(methods, name, "solver");
}
Preconditioner preconditioner_from_name(const std::string& name) {
    return from_name(preconditioners, name, "preconditioner");
}
std::string to_string(Method m) {
    return to_name(methods, m);
}
std::string to_string(Preconditioner p) {
    return to_name(preconditioners, p);
}

}  // namespace hexmesh::untangle
