// SPDX-License-Identifier: MIT
#include "dsm/config/option_registry.h"

#include <regex>
#include <sstream>

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
  WriteText(dir / "o.yaml", "occlusion: {depth_ratio: 1.5}\nrobust: {inlier_quantile: 0.9}\n");
  SystemOptions options;
  ApplyOptionsYaml(dir / "o.yaml", &options);
  EXPECT_FLOAT_EQ(options.occlusion.depth_ratio, 1.5f);
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

// --print-config's text: every key once, each with a value and a description, and read back it
// gives the options it was written from (defaults, and values that text could round: a double
// with no short decimal form, a float, a list, a name, the robust keys that set two models).
TEST(OptionsYaml, PrintedOptionsReadBackTheSame) {
  const SystemOptions defaults;
  const std::string text = OptionsYaml(defaults);
  std::istringstream lines(text);
  std::string line;
  int keys = 0, sections = 0;
  const std::regex key_line(R"(  [a-z_]+: (\[[0-9, ]*\]|[^ #]+)  # [-A-Za-z>.0-9_].{9,})");
  while (std::getline(lines, line)) {
    if (line.rfind("#", 0) == 0) continue;
    if (line.rfind("  ", 0) != 0) {
      ++sections;
      continue;
    }
    ++keys;
    EXPECT_TRUE(std::regex_match(line, key_line)) << line;
  }
  EXPECT_EQ(keys, 71);
  EXPECT_EQ(sections, 13);
  SystemOptions back;
  back.pba.levels = 1;  // Overwritten by the text.
  ApplyOptionsText(text, "printed", &back);
  EXPECT_EQ(OptionsYaml(back), text);
  EXPECT_EQ(back.pba.levels, defaults.pba.levels);

  SystemOptions changed;
  changed.pba.initial_lambda = 0.1 + 0.2;  // 0.30000000000000004
  changed.candidates.threshold_margin = 1.f / 3.f;
  changed.tracker.iterations = {3, 4, 5, 6};
  changed.interpolation = "bspline";
  changed.pba.robust.kind = changed.tracker.robust.kind = RobustKind::kHuberMad;
  changed.pba.robust.min_nu = changed.tracker.robust.min_nu = 2.5;
  changed.window.optimize_covisible_poses = true;
  const std::string changed_text = OptionsYaml(changed);
  EXPECT_NE(changed_text, text);
  SystemOptions read;
  ApplyOptionsText(changed_text, "printed", &read);
  EXPECT_EQ(OptionsYaml(read), changed_text);
  EXPECT_EQ(read.pba.initial_lambda, 0.1 + 0.2);
  EXPECT_EQ(read.candidates.threshold_margin, 1.f / 3.f);
  EXPECT_EQ(read.tracker.iterations, (std::vector<int>{3, 4, 5, 6}));
  EXPECT_EQ(read.tracker.robust.kind, RobustKind::kHuberMad);
  EXPECT_EQ(read.tracker.robust.min_nu, 2.5);
  EXPECT_TRUE(read.window.optimize_covisible_poses);
}

}  // namespace
}  // namespace dsm
