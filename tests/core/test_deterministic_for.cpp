#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include "hexmesh/core/deterministic_for.h"

using namespace hexmesh;

// Several indices throw: the error is the smallest one's, every time, and every index ran.
TEST(DeterministicFor, RethrowsTheSmallestFailingIndexAfterRunningAll) {
    for (int run = 0; run < 20; ++run) {
        std::vector<std::atomic<int>> ran(5000);
        try {
            deterministic_for(5000, [&](Id i) {
                ++ran[size_t(i)];
                if (i == 4321 || i == 777 || i == 2500)
                    throw std::invalid_argument(std::to_string(i));
            });
            ADD_FAILURE() << "nothing thrown";
        } catch (const std::invalid_argument& e) {
            EXPECT_EQ(std::string(e.what()), "777");
        }
        for (const auto& r : ran) EXPECT_EQ(r.load(), 1);
    }
}

TEST(DeterministicFor, RunsEveryIndexOnceWhenNothingThrows) {
    std::vector<std::atomic<int>> ran(1000);
    deterministic_for(1000, [&](Id i) { ++ran[size_t(i)]; });
    for (const auto& r : ran) EXPECT_EQ(r.load(), 1);
    deterministic_for(0, [&](Id) { ADD_FAILURE(); });
}
