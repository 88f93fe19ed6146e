// Test support for the readers: a scratch folder per test, and the message of a bad input.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/case_file.h"

namespace hexmesh::test {

// A fixture with a scratch folder private to this test process, removed after each test.
class ScratchFiles : public ::testing::Test {
  protected:
    // prefix: the start of the folder name in the temporary directory.
    explicit ScratchFiles(std::string prefix) : prefix_(std::move(prefix)) {}

    void SetUp() override {
        dir_ = std::filesystem::temp_directory_path() / (prefix_ + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(path(name), std::ios::binary) << text;
        return path(name);
    }

    std::filesystem::path dir_;

  private:
    std::string prefix_;
};

// The InputError message of read(file), or "" if it reads fine.
template <typename Read>
std::string input_error_of(Read read, const std::string& file) {
    try {
        read(file);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace hexmesh::test
