// SPDX-License-Identifier: MIT
#include <cstdio>

#include "apps/commands.h"
#include "dsm/io/dataset.h"

namespace dsm::cli {

Command AddInfo(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  auto gt = std::make_shared<GtArgs>();
  app.add_option("DATASET", *path, "Dataset folder (EuRoC, TUM monoVO, TUM RGB-D, KITTI or generic)")->required();
  AddGtOptions(app, gt.get());
  return [path, gt] {
    const Dataset dataset = OpenDataset(*path, gt->Parse());
    std::fputs(DescribeDataset(dataset).c_str(), stdout);
    return 0;
  };
}

}  // namespace dsm::cli
