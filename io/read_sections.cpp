// Stacks of planar cross-sections: the text format documented in io/sample_readers.h.
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "io/sample_readers.h"
#include "io/surface_formats.h"

namespace hexmesh {

SectionStack read_sections(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(fmt::format("{}: cannot open ({})", path, std::strerror(errno)));
    std::ostringstream buffer;
    buffer << in.rdbuf();
    const std::string data = buffer.str();

    SectionStack stack;
    std::vector<long long> section_line;  // where each section starts, for messages
    long long loop_line = 0;              // where the current polyline starts
    std::vector<std::string_view> tokens;
    const auto close_loop = [&]() {
        if (stack.sections.empty()) return;
        auto& loops = stack.sections.back().loops;
        if (loops.empty()) return;
        auto& loop = loops.back();
        if (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
        if (loop.size() < 3)
            throw InputError(
                fmt::format("{}: line {}: a closed polyline needs at least 3 points, "
                            "got {}",
                            path, loop_line, loop.size()));
    };
    surface_io::for_each_line(data, [&](long long number, std::string_view line) {
        const auto fail = [&](const std::string& message) {
            throw InputError(fmt::format("{}: line {}: {}", path, number, message));
        };
        const auto number_of = [&](std::string_view token) {
            double v = 0;
            if (!surface_io::parse_double(token, v))
                fail(fmt::format("expected a number, got '{}'", std::string(token.substr(0, 20))));
            if (!std::isfinite(v)) fail(fmt::format("numbers must be finite, got {}", v));
            return v;
        };
        surface_io::split_tokens(line.substr(0, line.find('#')), tokens);
        if (tokens.empty()) return true;
        if (tokens[0] == "slice") {
            if (tokens.size() != 2) fail("expected 'slice Z'");
            close_loop();
            stack.sections.push_back({number_of(tokens[1]), {{}}});
            section_line.push_back(number);
            loop_line = number;
        } else if (tokens[0] == "loop") {
            if (tokens.size() != 1) fail("expected 'loop' alone on its line");
            if (stack.sections.empty()) fail("'loop' before the first 'slice Z'");
            close_loop();
            stack.sections.back().loops.emplace_back();
            loop_line = number;
        } else {
            if (tokens.size() != 2)
                fail(fmt::format("expected 'slice Z', 'loop' or a point 'x y', got {} words",
                                 tokens.size()));
            const Eigen::Vector2d p(number_of(tokens[0]), number_of(tokens[1]));
            if (stack.sections.empty()) fail("a point before the first 'slice Z'");
            stack.sections.back().loops.back().push_back(p);
        }
        return true;
    });
    close_loop();
    if (stack.sections.size() < 2)
        throw InputError(fmt::format("{}: a stack of sections needs at least 2 'slice Z', got {}",
                                     path, stack.sections.size()));

    std::vector<size_t> order(stack.sections.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return stack.sections[a].z < stack.sections[b].z; });
    SectionStack sorted;
    for (size_t k = 0; k < order.size(); ++k) {
        if (k > 0 && stack.sections[order[k]].z == stack.sections[order[k - 1]].z)
            throw InputError(fmt::format("{}: line {}: a second slice at z = {} (line {})", path,
                                         section_line[order[k]], stack.sections[order[k]].z,
                                         section_line[order[k - 1]]));
        sorted.sections.push_back(std::move(stack.sections[order[k]]));
    }
    return sorted;
}

}  // namespace hexmesh
