// Test support: scratch files and folders a test program hands out, removed when it exits.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <system_error>

namespace hexmesh::test {

// The scratch paths (files or folders) handed out in this test process, removed when it
// exits unless a test failed: a failed test's files stay for a look (their paths are in its
// messages).
class ScratchRegistry {
  public:
    // gtest's UnitTest is made first so that it outlives this registry (asked at exit).
    ScratchRegistry() { ::testing::UnitTest::GetInstance(); }
    ~ScratchRegistry() {
        if (::testing::UnitTest::GetInstance()->Failed()) return;
        std::error_code ignored;
        for (const std::filesystem::path& path : paths_) std::filesystem::remove_all(path, ignored);
    }
    void add(const std::filesystem::path& path) { paths_.insert(path); }

  private:
    std::set<std::filesystem::path> paths_;
};

// Registers `path` for removal at exit and returns it.
inline std::filesystem::path remove_at_exit(const std::filesystem::path& path) {
    static ScratchRegistry registry;
    registry.add(path);
    return path;
}

}  // namespace hexmesh::test
