// SPDX-License-Identifier: MIT
#include <cstdio>

#include "apps/commands.h"
#include "dsm/report/report.h"

namespace dsm::cli {

Command AddReport(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  app.add_option("RUN_DIR", *dir, "Output folder of a dsm run")->required();
  return [dir] {
    WriteReport(*dir);
    std::printf("%s/report.html written\n", dir->c_str());
    return 0;
  };
}

}  // namespace dsm::cli
