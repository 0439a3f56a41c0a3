#pragma once
/// @file cli_test_utils.h
/// What the command-line tests share: running `barylab` as a user does (a child process, its
/// stdout and stderr captured, its exit code) and a fresh output folder per test.

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <sys/wait.h>

namespace barylab_test
{
/// What a `barylab` run returned: its exit code (-1 if it did not exit normally) and its
/// stdout + stderr.
struct CommandResult
{
  int code = -1;
  std::string output;
};

/// Runs `barylab ARGS` (the executable under test, BARYLAB_EXE) through the shell.
inline CommandResult RunBarylab(const std::string& args)
{
  const std::string command = std::string(BARYLAB_EXE) + " " + args + " 2>&1";
  CommandResult r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe)
    return r;
  std::array<char, 4096> buffer;
  while (fgets(buffer.data(), static_cast<int>(buffer.size()), pipe))
    r.output += buffer.data();
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// A bundled data file: BARYLAB_DATA_DIR/@p name.
inline std::string DataPath(const std::string& name)
{
  return std::string(BARYLAB_DATA_DIR) + "/" + name;
}

/// BARYLAB_TEST_OUTPUT_DIR/<@p prefix><the current test's name>, emptied and created.
inline std::filesystem::path FreshTestFolder(const std::string& prefix)
{
  const std::filesystem::path dir = std::filesystem::path(BARYLAB_TEST_OUTPUT_DIR) /
    (prefix + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}
} // namespace barylab_test
