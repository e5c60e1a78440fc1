// SPDX-License-Identifier: MIT
#include <cstdio>
#include <memory>
#include <string>

#include "apps/commands.h"
#include "dsm/mapfile/map_file.h"

namespace dsm::cli {

Command AddMap(CLI::App& app) {
  app.require_subcommand(1);
  CLI::App* info = app.add_subcommand("info", "Check a map file whole and describe it: maps, keyframes, points, bounds, camera, "
                                              "the dsm that wrote it");
  auto path = std::make_shared<std::string>();
  info->add_option("FILE", *path, "Map file (dsm run --save-map)")->required();
  return [info, path] {
    if (!info->parsed()) return 2;
    std::fputs(DescribeMapFile(*path, ReadMapFile(*path)).c_str(), stdout);
    return 0;
  };
}

}  // namespace dsm::cli
