// SPDX-License-Identifier: MIT
#include <cstdio>
#include <filesystem>

#include "apps/commands.h"
#include "dsm/io/dataset.h"
#include "dsm/io/euroc_copy.h"
#include "dsm/image/defects.h"
#include "dsm/util/check.h"

namespace dsm::cli {

Command AddDamage(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto defects = std::make_shared<std::string>();
  app.add_option("DATASET", *path, "EuRoC dataset folder")->required();
  app.add_option("--out", *out, "Output folder (EuRoC; the undamaged images are linked, not copied)")->required();
  app.add_option("--defects", *defects,
                 "Bad frames, as `dsm synth --defects`: KIND:FIRST[-LAST],... with KIND black, saturated, noise, "
                 "cover, corrupt, truncated, empty or cut, e.g. black:100-114,noise:160-174,corrupt:200,cover:240-280")
      ->required();
  return [path, out, defects] {
    const std::vector<Defect> spoiled = ParseDefects(*defects);  // Bad spec: before anything is written.
    const Dataset dataset = OpenDataset(*path);
    if (dataset.format != "euroc") throw InputError(*path + ": `dsm damage` copies EuRoC folders; this one is " + dataset.format);
    namespace fs = std::filesystem;
    if (fs::exists(*out) && !fs::is_empty(*out)) throw InputError(*out + ": the output folder exists and is not empty");
    WriteEurocCopy(*path, *out, dataset.size(), GroundTruthConvention{}, *defects);
    std::printf("%s: %zu frames of %s with %zu defects\n", out->c_str(), dataset.size(), path->c_str(), spoiled.size());
    return 0;
  };
}

}  // namespace dsm::cli
