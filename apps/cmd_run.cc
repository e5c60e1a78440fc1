// SPDX-License-Identifier: MIT
#include <cstdio>

#include "apps/commands.h"
#include "dsm/io/options_io.h"
#include "dsm/run/run.h"
#include "dsm/util/check.h"

namespace dsm::cli {

Command AddRun(CLI::App& app) {
  struct Args {
    std::string dataset, out = "dsm_out", mode = "sw", config;
    int start = 0, end = -1;
    bool quiet = false;
  };
  auto a = std::make_shared<Args>();
  app.add_option("DATASET", a->dataset, "Dataset folder")->required();
  app.add_option("--out", a->out, "Output folder (default ./dsm_out)");
  app.add_option("--mode", a->mode, "sw (temporal window, DSM-SW) | dsm (persistent map, not available yet)");
  app.add_option("--config", a->config, "YAML file with options (see README)");
  app.add_option("--start", a->start, "First frame index");
  app.add_option("--end", a->end, "One past the last frame index");
  app.add_flag("--quiet", a->quiet, "Print only the summary");
  return [a] {
    RunOptions options;
    if (a->mode == "sw") {
      options.system.mode = MapMode::kSlidingWindow;
    } else if (a->mode == "dsm") {
      options.system.mode = MapMode::kFull;
    } else {
      throw InputError("--mode: expected sw or dsm, got '" + a->mode + "'");
    }
    if (!a->config.empty()) ApplyOptionsYaml(a->config, &options.system);
    options.system.Validate();
    options.start = a->start;
    options.end = a->end;
    options.quiet = a->quiet;
    const Dataset dataset = OpenDataset(a->dataset);
    const RunSummary summary = RunDataset(dataset, options, a->out);
    std::printf("%s\n", summary.line.c_str());
    return 0;
  };
}

}  // namespace dsm::cli
