#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace orcs::test_support {
namespace {

namespace fs = std::filesystem;

// "Suite_Name" of the running test, with anything but letters, digits and '_' (the '/' of parameterised
// tests, say) made '_'; "no_test" outside a test.
std::string CurrentTestName() {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info == nullptr ? "no_test" : std::string(info->test_suite_name()) + "_" + info->name();
  std::replace_if(
      name.begin(), name.end(), [](unsigned char c) { return std::isalnum(c) == 0 && c != '_'; }, '_');
  return name;
}

}  // namespace

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  path_ = fs::temp_directory_path() /
          ("orcs_" + CurrentTestName() + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  fs::remove_all(path_);  // a leftover of an earlier process with the same id
  if (!fs::create_directories(path_)) throw std::runtime_error("cannot make the directory " + path_.string());
}

TempDir::~TempDir() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

std::string TempDir::PathOf(const std::string& relative_name) const { return (path_ / relative_name).string(); }

std::string TempDir::Write(const std::string& relative_name, const std::string& contents) const {
  const fs::path file = path_ / relative_name;
  fs::create_directories(file.parent_path());
  std::ofstream out(file);
  out << contents;
  out.close();
  if (!out) throw std::runtime_error("cannot write " + file.string());
  return file.string();
}

std::string TempDir::Read(const std::string& relative_name_or_absolute_path) const {
  std::ifstream in(path_ / relative_name_or_absolute_path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

std::vector<std::string> TempDir::FileNames() const {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(path_)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace orcs::test_support
