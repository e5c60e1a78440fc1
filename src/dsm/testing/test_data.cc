// SPDX-License-Identifier: MIT
#include "dsm/testing/test_data.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "dsm/util/check.h"

namespace dsm::testing {

namespace fs = std::filesystem;

fs::path SharedDataDir() {
  if (const char* env = std::getenv("DSM_SHARED_DATA")) return fs::path(env);
  return fs::path("../shared/data");
}

fs::path ScratchDir(const std::string& name) {
  const char* env = std::getenv("DSM_BINARY_DIR");
  const fs::path root = env ? fs::path(env) / "test_scratch" : fs::temp_directory_path() / "dsm_test";
  const fs::path dir = root / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

fs::path WriteText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path);
  out << text;
  DSM_CHECK(out.good(), "cannot write " + path.string());
  return path;
}

CommandResult RunCommand(const std::string& command) {
  CommandResult r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) r.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace dsm::testing
