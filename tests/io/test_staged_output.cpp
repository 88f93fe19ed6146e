#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

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
    // Beside the folder: .NAME.staging-HOST-PID.
    const std::string stem = "." + dir.filename().string() + ".staging-";
    const fs::path dead =
        dir.parent_path() / (stem + std::string(host) + "-" + std::to_string(child));
    const fs::path live =
        dir.parent_path() / (stem + std::string(host) + "-" + std::to_string(getppid()));
    const fs::path other_host = dir.parent_path() / (stem + "elsewhere-" + std::to_string(child));
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
    for (const fs::path& p : {dir, live, other_host}) fs::remove_all(p);
}

namespace {

std::string text_of(const fs::path& file) {
    std::ifstream in(file);
    std::string text;
    std::getline(in, text);
    return text;
}

// The entries of `dir` (names), sorted.
std::vector<std::string> entries(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace

TEST(StagedOutput, AKillAtAnyStepOfTheCommitLeavesTheOldResultOrTheNewOneWhole) {
    const fs::path dir = fs::temp_directory_path() / "hexmesh_test_staged_kill";
    for (const std::string kill_at : {"writing", "carried", "exchanged"}) {
        SCOPED_TRACE(kill_at);
        fs::remove_all(dir);
        fs::create_directories(dir / "grid");
        std::ofstream(dir / "quality.json") << "old";
        std::ofstream(dir / "grid.vtm") << "old";
        std::ofstream(dir / "grid" / "block0.vts") << "old";
        std::ofstream(dir / "notes.txt") << "user file";
        const pid_t child = fork();
        if (child == 0) {
            StagedOutput::commit_step_hook = [&](const char* step) {
                if (kill_at == step) ::raise(SIGKILL);
            };
            StagedOutput out(dir.string());
            out.write_text("quality.json", "new");
            out.write_text("grid.vtm", "new");
            fs::create_directories(fs::path(out.path("grid")));
            std::ofstream(fs::path(out.path("grid")) / "block0.vts") << "new";
            if (kill_at == "writing") ::raise(SIGKILL);
            out.commit();
            _exit(0);
        }
        int status = 0;
        waitpid(child, &status, 0);
        ASSERT_TRUE(WIFSIGNALED(status));
        const std::string seen = text_of(dir / "quality.json");
        const std::string expected = kill_at == "exchanged" ? "new" : "old";
        EXPECT_EQ(seen, expected);
        EXPECT_EQ(text_of(dir / "grid.vtm"), expected);
        EXPECT_EQ(text_of(dir / "grid" / "block0.vts"), expected);
        EXPECT_EQ(text_of(dir / "notes.txt"), "user file");
        EXPECT_EQ(entries(dir),
                  (std::vector<std::string>{"grid", "grid.vtm", "notes.txt", "quality.json"}));
        // The next run cleans what the killed one left beside the folder, and commits.
        {
            StagedOutput out(dir.string());
            out.write_text("quality.json", "next");
            out.commit();
        }
        EXPECT_EQ(text_of(dir / "quality.json"), "next");
        EXPECT_EQ(text_of(dir / "grid.vtm"), expected);
        for (const auto& e : fs::directory_iterator(dir.parent_path()))
            EXPECT_EQ(e.path().filename().string().rfind(".hexmesh_test_staged_kill.staging-", 0),
                      std::string::npos)
                << e.path();
    }
    fs::remove_all(dir);
}

TEST(StagedOutput, ASecondWriterOfTheSameFolderIsRefusedWhileTheFirstWorks) {
    const fs::path dir = fs::temp_directory_path() / "hexmesh_test_staged_lock";
    fs::remove_all(dir);
    {
        StagedOutput first(dir.string());
        first.write_text("quality.json", "first");
        try {
            StagedOutput second(dir.string());
            FAIL() << "expected a refusal";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(
                std::string(e.what()).find("another hexmesh process is writing into this folder"),
                std::string::npos)
                << e.what();
        }
        first.commit();
    }
    EXPECT_EQ(text_of(dir / "quality.json"), "first");
    StagedOutput third(dir.string());  // free again
    fs::remove_all(dir);
}

TEST(StagedOutput, ALinkToAFolderStaysALinkAndTheFolderTakesTheResult) {
    const fs::path base = fs::temp_directory_path() / "hexmesh_test_staged_link";
    fs::remove_all(base);
    fs::create_directories(base / "real");
    fs::create_directory_symlink(base / "real", base / "link");
    {
        StagedOutput out((base / "link").string());
        out.write_text("quality.json", "new");
        const auto files = out.commit();
        ASSERT_EQ(files.size(), 1u);
    }
    EXPECT_TRUE(fs::is_symlink(base / "link"));
    EXPECT_EQ(text_of(base / "real" / "quality.json"), "new");
    fs::remove_all(base);
}

TEST(StagedOutput, NamedEntriesReplaceOnlyWhatIsWrittenAndLeaveTheFolderItself) {
    // A file exported into a user's folder (or the current one): that folder is not swapped,
    // locked or copied, only the written entry is replaced.
    const fs::path dir = fs::temp_directory_path() / "hexmesh_test_staged_entries";
    fs::remove_all(dir);
    fs::create_directories(dir / "project");
    std::ofstream(dir / "grid.msh") << "old";
    std::ofstream(dir / "project" / "notes.txt") << "user file";
    struct stat before {};
    ASSERT_EQ(::stat(dir.c_str(), &before), 0);
    {
        StagedOutput first(dir.string(), StagedOutput::Scope::named_entries);
        StagedOutput second(dir.string(), StagedOutput::Scope::named_entries);  // no lock
        first.write_text("grid.msh", "new");
        first.commit();
    }
    struct stat after {};
    ASSERT_EQ(::stat(dir.c_str(), &after), 0);
    EXPECT_EQ(before.st_ino, after.st_ino);
    EXPECT_EQ(text_of(dir / "grid.msh"), "new");
    EXPECT_EQ(text_of(dir / "project" / "notes.txt"), "user file");
    EXPECT_EQ(entries(dir), (std::vector<std::string>{"grid.msh", "project"}));
    fs::remove_all(dir);
}
