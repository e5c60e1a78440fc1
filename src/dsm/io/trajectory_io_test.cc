// SPDX-License-Identifier: MIT
#include "dsm/io/trajectory_io.h"

#include <gtest/gtest.h>

#include "dsm/testing/test_data.h"
#include "dsm/util/check.h"

namespace dsm {
namespace {

using testing::ScratchDir;
using testing::WriteText;

TEST(TrajectoryIo, TumRoundTripKeepsNanoseconds) {
  const auto dir = ScratchDir("trajectory_io_roundtrip");
  Trajectory t;
  Eigen::Matrix<double, 6, 1> xi;
  xi << 1, 2, 3, 0.1, 0.2, 0.3;
  t.Add(1403636584763555584LL, SE3d::Exp(xi));
  t.Add(1403636584813555456LL, SE3d());
  WriteTumTrajectory(dir / "t.tum", t);
  EXPECT_EQ(DetectTrajectoryFormat(dir / "t.tum"), TrajectoryFormat::kTum);
  const Trajectory back = ReadTrajectory(dir / "t.tum", TrajectoryFormat::kTum);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back.stamps_ns[0], 1403636584763555584LL);
  EXPECT_EQ(back.stamps_ns[1], 1403636584813555456LL);
  EXPECT_LT((back.poses[0].Matrix() - t.poses[0].Matrix()).norm(), 1e-8);
}

TEST(TrajectoryIo, DetectsAndReadsEurocAndKitti) {
  const auto dir = ScratchDir("trajectory_io_formats");
  WriteText(dir / "e.csv", "#timestamp,x,y,z,qw,qx,qy,qz\n100,1,2,3,1,0,0,0\n200,1,2,4,0,1,0,0\n");
  EXPECT_EQ(DetectTrajectoryFormat(dir / "e.csv"), TrajectoryFormat::kEuroc);
  const Trajectory e = ReadTrajectory(dir / "e.csv", TrajectoryFormat::kEuroc);
  EXPECT_EQ(e.stamps_ns[1], 200);
  EXPECT_NEAR(e.poses[1].Rotation()(1, 1), -1.0, 1e-12);  // 180 deg about x
  WriteText(dir / "k.txt", "1 0 0 5 0 1 0 6 0 0 1 7\n");
  EXPECT_EQ(DetectTrajectoryFormat(dir / "k.txt"), TrajectoryFormat::kKitti);
  const Trajectory k = ReadTrajectory(dir / "k.txt", TrajectoryFormat::kKitti);
  EXPECT_FALSE(k.HasStamps());
  EXPECT_EQ(k.poses[0].Translation(), Eigen::Vector3d(5, 6, 7));
}

TEST(TrajectoryIo, MalformedFilesNameFileAndLine) {
  const auto dir = ScratchDir("trajectory_io_bad");
  WriteText(dir / "bad.tum", "# header\n0 0 0 0 0 0 0 1\n1 0 0 x 0 0 0 1\n");
  try {
    ReadTrajectory(dir / "bad.tum", TrajectoryFormat::kTum);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.tum:3"), std::string::npos) << e.what();
  }
  WriteText(dir / "short.tum", "0 0 0 0 0 0 1\n");
  EXPECT_THROW(ReadTrajectory(dir / "short.tum", TrajectoryFormat::kTum), InputError);
  EXPECT_THROW(DetectTrajectoryFormat(dir / "short.tum"), InputError);
  WriteText(dir / "empty.tum", "# nothing\n");
  EXPECT_THROW(ReadTrajectory(dir / "empty.tum", TrajectoryFormat::kTum), InputError);
  WriteText(dir / "zeroq.tum", "0 0 0 0 0 0 0 0\n");
  EXPECT_THROW(ReadTrajectory(dir / "zeroq.tum", TrajectoryFormat::kTum), InputError);
  // A quaternion whose squared norm overflows: normalising it would give no rotation at all.
  WriteText(dir / "hugeq.csv", "1403636584213555456,4.7,0.9,0.5,-2.066935e154,-0.15,-0.83,-0.08\n");
  try {
    ReadTrajectory(dir / "hugeq.csv", TrajectoryFormat::kEuroc);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("hugeq.csv:1: the quaternion's norm is implausible"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(ReadTrajectory(dir / "missing.tum", TrajectoryFormat::kTum), InputError);
  EXPECT_THROW(ParseTrajectoryFormat("csv", "--ref-format"), InputError);
}

}  // namespace
}  // namespace dsm
