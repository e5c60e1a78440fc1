// SPDX-License-Identifier: MIT
#include "dsm/io/options_io.h"

#include <gtest/gtest.h>

#include "dsm/testing/input_error.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

using testing::MessageOf;
using testing::ScratchDir;
using testing::WriteText;

TEST(OptionsYaml, SetsTheKeysItNamesAndLeavesTheRest) {
  const auto dir = ScratchDir("options_yaml");
  WriteText(dir / "o.yaml", "occlusion: {candidate_interval: 0.25}\nrobust: {inlier_quantile: 0.9}\n");
  SystemOptions options;
  ApplyOptionsYaml(dir / "o.yaml", &options);
  EXPECT_FLOAT_EQ(options.occlusion.candidate_interval, 0.25f);
  // One key, both error models: the adjustment's and the tracker's.
  EXPECT_DOUBLE_EQ(options.pba.robust.inlier_quantile, 0.9);
  EXPECT_DOUBLE_EQ(options.tracker.robust.inlier_quantile, 0.9);
  const SystemOptions defaults;
  EXPECT_EQ(options.pba.levels, defaults.pba.levels);
  EXPECT_EQ(options.window.temporal_keyframes, defaults.window.temporal_keyframes);
}

TEST(OptionsYaml, NoFileNoSettings) {
  // /dev/null (or an empty file) is a valid options file without settings, as `--config /dev/null`.
  SystemOptions options;
  options.pba.levels = 3;
  ApplyOptionsYaml("/dev/null", &options);
  EXPECT_EQ(options.pba.levels, 3);
  const auto dir = ScratchDir("options_yaml_bad");
  EXPECT_NE(MessageOf([&] { ApplyOptionsYaml(dir / "none.yaml", &options); }).find("none.yaml: file not found"),
            std::string::npos);
  EXPECT_NE(MessageOf([&] { ApplyOptionsYaml(dir, &options); }).find("a folder, not a YAML file"), std::string::npos);
  WriteText(dir / "key.yaml", "occlusion: {candidate_share: 0.25}\n");
  EXPECT_NE(MessageOf([&] { ApplyOptionsYaml(dir / "key.yaml", &options); }).find("occlusion.candidate_share"),
            std::string::npos);
}

}  // namespace
}  // namespace dsm
