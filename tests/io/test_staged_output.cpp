#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <sys/wait.h>
#include <unistd.h>

#include "io/staged_output.h"

using namespace hexmesh;
namespace fs = std::filesystem;

TEST(StagedOutput, NothingIsLeftWhenTheRunFails) {
    const fs::path dir = fs::temp_directory_path() / "hexmesh_test_staged_fail";
    fs::remove_all(dir);
    try {
        StagedOutput out(dir.string());
        out.write_text("quality.json", "{}");
        throw std::runtime_error("writer failed");
    } catch (const std::runtime_error&) {
    }
    EXPECT_FALSE(fs::exists(dir));
}

TEST(StagedOutput, CommitMovesFilesAndReplacesOldOutputs) {
    const fs::path dir = fs::temp_directory_path() / "hexmesh_test_staged_ok";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "quality.json") << "old";
    std::ofstream(dir / "notes.txt") << "user file";
    {
        StagedOutput out(dir.string());
        out.write_text("quality.json", "new");
        const auto files = out.commit();
        ASSERT_EQ(files.size(), 1u);
        EXPECT_EQ(files[0], (dir / "quality.json").string());
    }
    std::ifstream in(dir / "quality.json");
    std::string text;
    in >> text;
    EXPECT_EQ(text, "new");
    in.close();
    EXPECT_TRUE(fs::exists(dir / "notes.txt"));
    int entries = 0;
    for (const auto& e : fs::directory_iterator(dir)) entries += e.is_regular_file();
    EXPECT_EQ(entries, 2);  // no staging leftovers
    fs::remove_all(dir);
}

TEST(StagedOutput, UnwritableDirectoryIsAClearError) {
    EXPECT_THROW(StagedOutput("/proc/hexmesh_cannot_write_here"), std::runtime_error);
}

TEST(StagedOutput, StagingLeftByAKilledRunOnThisHostIsRemoved) {
    const fs::path dir = fs::temp_directory_path() / "hexmesh_test_staged_stale";
    fs::remove_all(dir);
    fs::create_directories(dir);
    char host[256] = {};
    ASSERT_EQ(gethostname(host, sizeof host - 1), 0);
    // A process that has ended: its pid is free (until reused, which a few microseconds make
    // unlikely).
    const pid_t child = fork();
    if (child == 0) _exit(0);
    ASSERT_GT(child, 0);
    waitpid(child, nullptr, 0);
    const fs::path dead = dir / (".staging-" + std::string(host) + "-" + std::to_string(child));
    const fs::path live = dir / (".staging-" + std::string(host) + "-" + std::to_string(getppid()));
    const fs::path other_host = dir / (".staging-elsewhere-" + std::to_string(child));
    for (const fs::path& p : {dead, live, other_host}) {
        fs::create_directories(p);
        std::ofstream(p / "grid.vtm") << "partial";
    }
    {
        StagedOutput out(dir.string());
        out.write_text("quality.json", "{}");
        out.commit();
    }
    EXPECT_FALSE(fs::exists(dead));
    EXPECT_TRUE(fs::exists(live));
    EXPECT_TRUE(fs::exists(other_host));
    EXPECT_TRUE(fs::exists(dir / "quality.json"));
    fs::remove_all(dir);
}
