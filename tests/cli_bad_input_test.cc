// SPDX-License-Identifier: MIT
// Bad input to `dsm`, as a user gives it: every case is a clear message naming what is wrong, with
// exit code 2, never a crash (the rest of the command line: cli_test.cc).
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dsm/testing/test_data.h"
#include "cli.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;
using testing::Contains;
using testing::Result;
using testing::RunDsm;
using testing::ScratchDir;
using testing::SharedDataDir;
using testing::WriteText;

TEST(Cli, BadInputIsAClearErrorWithExitCode2) {
  const fs::path dir = ScratchDir("cli_bad");
  const fs::path traj = SharedDataDir() / "trajectories";
  struct Case {
    std::string args, expected;
  };
  WriteText(dir / "broken.tum", "0 0 0 0 0 0 0 1\n1 0 0 oops 0 0 0 1\n");
  fs::create_directories(dir / "badcam" / "images");
  WriteText(dir / "bad_config.yaml", "pba: {speed: 11}\n");
  WriteText(dir / "bad_value.yaml", "window: {temporal_keyframes: 1}\n");
  WriteText(dir / "bad_interpolation.yaml", "system: {interpolation: bicubic}\n");
  WriteText(dir / "bad_texture_loss.yaml", "system: {texture_loss_min_noise: -1}\n");
  WriteText(dir / "no_vocabulary.yaml", "loop_closure: {vocabulary: " + (dir / "none.voc").string() + "}\n");
  WriteText(dir / "bad.voc", "DSMVOC01 but not a vocabulary");
  WriteText(dir / "bad_vocabulary.yaml", "loop_closure: {vocabulary: " + (dir / "bad.voc").string() + "}\n");
  WriteText(dir / "badcam" / "camera.yaml", "model: pinhole\nwidth: 640\nheight: 480\nintrinsics: [400, 400, 320]\n");
  ASSERT_EQ(RunDsm("synth --scene shake --frames 2 --width 160 --height 120 --out " + (dir / "generic").string()).code, 0);
  // A calibration whose size fits no frame of the recording: the generic scene's images, 640x480 in
  // its camera.yaml.
  fs::create_directories(dir / "wrong_size");
  fs::create_directory_symlink(fs::absolute(dir / "generic" / "images"), dir / "wrong_size" / "images");
  WriteText(dir / "wrong_size" / "camera.yaml",
            "model: pinhole\nwidth: 640\nheight: 480\nintrinsics: [400, 400, 320, 240]\n");
  // Map files: empty, not a zip, a real one cut short.
  WriteText(dir / "empty.dsmmap", "");
  WriteText(dir / "text.dsmmap", "keyframes: 3\n");
  ASSERT_EQ(RunDsm("run " + (dir / "generic").string() + " --out " + (dir / "g").string() + " --quiet --save-map " +
                   (dir / "g.dsmmap").string())
                .code,
            0);
  {
    std::ifstream in(dir / "g.dsmmap", std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(dir / "cut.dsmmap", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  const std::vector<Case> cases = {
      {"map info " + (dir / "empty.dsmmap").string(), "empty.dsmmap: not a readable zip archive"},
      {"map info " + (dir / "text.dsmmap").string(), "text.dsmmap: not a readable zip archive"},
      {"map info " + (dir / "cut.dsmmap").string(), "cut.dsmmap"},
      {"map info " + dir.string(), dir.string() + ": not a file"},
      {"map info " + (dir / "none.dsmmap").string(), "none.dsmmap: no such file"},
      {"run " + (dir / "generic").string() + " --out " + (dir / "o").string() + " --load-map " +
           (dir / "cut.dsmmap").string(),
       "cut.dsmmap"},
      {"run " + (dir / "generic").string() + " --out " + (dir / "o").string() + " --load-map " +
           (dir / "g.dsmmap").string(),
       "g.dsmmap: the map file holds no map with keyframes"},
      {"run " + (dir / "generic").string() + " --out " + (dir / "o").string() + " --save-map " + dir.string(),
       "--save-map names a folder"},
      {"run " + (dir / "generic").string() + " --out " + (dir / "o").string() + " --localize",
       "--localize needs a map to localise in (--load-map)"},
      {"info " + (dir / "nothing").string(), "not found"},
      {"info " + dir.string(), "cannot detect"},
      {"info " + (dir / "badcam").string(), "intrinsics"},
      {"eval --ref " + (dir / "missing.tum").string() + " --est " + (dir / "broken.tum").string(), "missing.tum"},
      {"eval --ref " + (traj / "fr2_desk_groundtruth.txt").string() + " --est " + (dir / "broken.tum").string(),
       "broken.tum:2"},
      {"eval --ref " + (traj / "KITTI_00_gt.txt").string() + " --est " + (traj / "KITTI_00_ORB.txt").string() +
           " --align affine",
       "--align"},
      {"eval --ref " + (traj / "KITTI_00_gt.txt").string() + " --est " + (traj / "fr2_desk_ORB.txt").string(),
       "pose by pose"},
      {"synth --scene moon --out " + (dir / "x").string(), "unknown scene"},
      {"synth --scene loop --out " + (dir / "x").string() + " --width 5", "--width"},
      {"run " + (dir / "badcam").string() + " --robust cauchy", "--robust"},
      {"run " + (dir / "badcam").string() + " --nc 99", "window.covisible_keyframes"},
      {"run " + (dir / "badcam").string() + " --nc -3", "--nc -3: window.covisible_keyframes must be within 0..20"},
      {"run " + (dir / "badcam").string() + " --nt 1", "--nt 1: window.temporal_keyframes"},
      {"run " + (dir / "badcam").string() + " --pba-levels 0", "--pba-levels 0: pba.levels"},
      {"run " + (dir / "wrong_size").string() + " --out " + (dir / "o").string(),
       (dir / "wrong_size" / "camera.yaml").string() + ": the calibration does not fit the recording: "},
      {"run " + (dir / "wrong_size").string() + " --out " + (dir / "o").string(),
       "image is 160x120 but the calibration says 640x480"},
      {"run " + (dir / "badcam").string() + " --mode fast", "--mode"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --config " + (dir / "bad_config.yaml").string(),
       "unknown key 'pba.speed'"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --config " + (dir / "bad_value.yaml").string(),
       "window.temporal_keyframes"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --config " + dir.string(),
       "a folder, not a YAML file"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --config " +
           (dir / "bad_interpolation.yaml").string(),
       "system.interpolation must be auto, bilinear or bspline, not 'bicubic'"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --config " +
           (dir / "bad_texture_loss.yaml").string(),
       "system.texture_loss_min_noise must be non-negative"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --out " + (dir / "o").string() + " --config " +
           (dir / "no_vocabulary.yaml").string(),
       "none.voc: cannot open the vocabulary file"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --out " + (dir / "o").string() + " --config " +
           (dir / "bad_vocabulary.yaml").string(),
       "bad.voc: not a dsm vocabulary file"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --start 500 --out " + (dir / "o").string(), "--start"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --gt-frame imu", "--gt-frame"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --line-delay-us 200", "--line-delay-us must be"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --view-wait 5", "--view-wait needs --view"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --view --view-wait -1", "--view-wait must be"},
      {"run " + (SharedDataDir() / "euroc_mh01_shake").string() + " --start 339 --out " + (dir / "o").string(),
       "at least two frames"},
      {"synth --scene loop --out " + (dir / "x").string() + " --defects fog:3", "--defects: unknown kind 'fog'"},
      {"damage " + (SharedDataDir() / "euroc_mh01_shake").string() + " --out " + (dir / "d").string() +
           " --defects fog:3",
       "--defects: unknown kind 'fog'"},
      {"damage " + (dir / "generic").string() + " --out " + (dir / "d").string() + " --defects black:3",
       "copies EuRoC folders; this one is folder"},
      {"damage " + (SharedDataDir() / "euroc_mh01_shake").string() + " --out " + (dir / "badcam").string() +
           " --defects black:3",
       "is not empty"},
      {"info " + (dir / "badcam").string() + " --gt-quaternion jpl", "EuRoC datasets only"},
      {"info " + (SharedDataDir() / "euroc_mh01_shake").string() + " --gt-out " + (dir / "no" / "gt.tum").string(),
       "gt.tum: cannot write"},
      {"gt-check " + (SharedDataDir() / "euroc_mh01_shake").string() + " --gap 0", "gap"},
      {"run --out " + (dir / "o").string(), "DATASET is required"},
      {"run --print-config --nc -1", "--nc -1"},
      {"frobnicate", ""},
      {"eval --ref", ""},
  };
  for (const Case& c : cases) {
    const Result r = RunDsm(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_TRUE(Contains(r.output, c.expected)) << c.args << "\n" << r.output;
  }
}

}  // namespace
}  // namespace dsm
