// SPDX-License-Identifier: MIT
#include "dsm/mapfile/map_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "dsm/mapfile/zip_archive.h"
#include "dsm/optimization/pba_world.h"
#include "dsm/testing/input_error.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

using ::testing::HasSubstr;

std::string Bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void WriteBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// A map of four rendered keyframes with every field the file holds set to something of its own:
// a fitted error model, a signature, a released pyramid, a removed point, outlier observations,
// the window and the covisibility; and a second, empty map.
MapFile SampleFile() {
  testing::World w;
  testing::BuildWorld({0, 6, 12, 18}, &w);
  MapFile file;
  file.created_by = "dsm test";
  file.camera = w.seq.camera;
  file.options = "window:\n  temporal_keyframes: 4\n";
  for (int k = 0; k < w.map.NumKeyframes(); ++k) {
    Keyframe& kf = w.map.keyframe(k);
    kf.t_ns = 1000000000LL + k * 33333333LL;
    kf.affine = {0.01 * k, -0.5 * k};
    kf.exposure = 1.0 + 0.25 * k;
    kf.error_model.sigma = 6.0 + k;
    kf.error_model.nu = 3.5;
    kf.error_model.fitted = k % 2 == 1;
    kf.most_pba_links = 100 * k;
    kf.signature = ComputeSignature(kf.Pyramid());
  }
  w.map.ReleaseUnusedPyramids(0);  // Every keyframe keeps its image alone, as old keyframes do.
  w.map.point(3).removed = true;
  w.map.point(5).observations[1].outlier = true;
  StoredMap stored;
  stored.map = std::move(w.map);
  stored.window = {0, 1, 2, 3};
  stored.covisible = {};
  stored.covisibility = {{}, {}, {0}, {0, 1}};
  stored.image_noise_sigma = 2.75;
  stored.residual_level = 3.125;
  stored.texture_level = 41.5;
  file.maps.push_back(std::move(stored));
  file.maps.emplace_back();
  return file;
}

void ExpectSameMaps(const MapFile& a, const MapFile& b) {
  EXPECT_EQ(a.created_by, b.created_by);
  EXPECT_EQ(a.options, b.options);
  EXPECT_EQ(a.camera.width, b.camera.width);
  EXPECT_EQ(a.camera.fx, b.camera.fx);
  EXPECT_EQ(a.camera.cy, b.camera.cy);
  ASSERT_EQ(a.maps.size(), b.maps.size());
  for (size_t m = 0; m < a.maps.size(); ++m) {
    const Map& x = a.maps[m].map;
    const Map& y = b.maps[m].map;
    EXPECT_EQ(a.maps[m].window, b.maps[m].window);
    EXPECT_EQ(a.maps[m].covisible, b.maps[m].covisible);
    EXPECT_EQ(x.interpolation(), y.interpolation());
    EXPECT_EQ(a.maps[m].image_noise_sigma, b.maps[m].image_noise_sigma);
    EXPECT_EQ(a.maps[m].residual_level, b.maps[m].residual_level);
    EXPECT_EQ(a.maps[m].texture_level, b.maps[m].texture_level);
    ASSERT_EQ(x.NumKeyframes(), y.NumKeyframes());
    ASSERT_EQ(x.NumPoints(), y.NumPoints());
    for (int k = 0; k < x.NumKeyframes(); ++k) {
      const Keyframe& p = x.keyframe(k);
      const Keyframe& q = y.keyframe(k);
      EXPECT_EQ(p.frame_index, q.frame_index);
      EXPECT_EQ(p.t_ns, q.t_ns);
      EXPECT_EQ(p.cam_from_world.Matrix(), q.cam_from_world.Matrix());
      EXPECT_EQ(p.affine.a, q.affine.a);
      EXPECT_EQ(p.affine.b, q.affine.b);
      EXPECT_EQ(p.exposure, q.exposure);
      EXPECT_EQ(p.error_model.kind, q.error_model.kind);
      EXPECT_EQ(p.error_model.sigma, q.error_model.sigma);
      EXPECT_EQ(p.error_model.nu, q.error_model.nu);
      EXPECT_EQ(p.error_model.inlier_threshold, q.error_model.inlier_threshold);
      EXPECT_EQ(p.error_model.fitted, q.error_model.fitted);
      EXPECT_EQ(p.pyramid_levels, q.pyramid_levels);
      EXPECT_EQ(p.most_pba_links, q.most_pba_links);
      EXPECT_EQ(p.signature.texture, q.signature.texture);
      EXPECT_EQ(p.signature.thumbnail, q.signature.thumbnail);
      EXPECT_EQ(p.points, q.points);
      const Image<uint16_t> ip = p.Level0(), iq = q.Level0();
      ASSERT_EQ(ip.size(), iq.size());
      EXPECT_TRUE(std::equal(ip.data(), ip.data() + ip.size(), iq.data())) << "keyframe " << k;
      if (static_cast<size_t>(k) < a.maps[m].covisibility.size()) {
        EXPECT_EQ(a.maps[m].covisibility[k], b.maps[m].covisibility[k]);
      }
    }
    for (int i = 0; i < x.NumPoints(); ++i) {
      const Point& p = x.point(i);
      const Point& q = y.point(i);
      EXPECT_EQ(p.host, q.host);
      EXPECT_EQ(p.pixel, q.pixel);
      EXPECT_EQ(p.idepth, q.idepth);
      EXPECT_EQ(p.removed, q.removed);
      EXPECT_EQ(p.patch_ok, q.patch_ok);
      EXPECT_EQ(p.patch.value, q.patch.value);
      EXPECT_EQ(p.patch.weight_g, q.patch.weight_g);
      ASSERT_EQ(p.observations.size(), q.observations.size());
      for (size_t j = 0; j < p.observations.size(); ++j) {
        EXPECT_EQ(p.observations[j].target, q.observations[j].target);
        EXPECT_EQ(p.observations[j].outlier, q.observations[j].outlier);
      }
    }
  }
}

TEST(MapFile, ReadsBackWhatItWroteAndWritesItAgainByteForByte) {
  const std::filesystem::path dir = testing::ScratchDir("map_file_round_trip");
  const MapFile file = SampleFile();
  ASSERT_GT(file.maps[0].map.NumPoints(), 500);
  WriteMapFile(dir / "a.dsmap", file);
  const MapFile read = ReadMapFile(dir / "a.dsmap");
  ExpectSameMaps(file, read);
  // A restored keyframe rebuilds the pyramid it had.
  const Keyframe& kf = read.maps[0].map.keyframe(2);
  const auto pyramid = kf.PyramidOrRebuilt();
  EXPECT_EQ(pyramid->levels(), 4);
  EXPECT_EQ(ComputeSignature(*pyramid).texture, kf.signature.texture);
  WriteMapFile(dir / "b.dsmap", read);
  EXPECT_EQ(Bytes(dir / "a.dsmap"), Bytes(dir / "b.dsmap"));
  const std::string info = DescribeMapFile(dir / "a.dsmap", read);
  EXPECT_THAT(info, HasSubstr("maps:       2"));
  EXPECT_THAT(info, HasSubstr("4 keyframes (frames 0-18)"));
  EXPECT_THAT(info, HasSubstr(std::to_string(read.maps[0].map.NumLivePoints()) + " points (1 removed)"));
}

// Rewrites the map file at `from` into `to` with its manifest changed by `edit`.
void EditManifest(const std::filesystem::path& from, const std::filesystem::path& to,
                  const std::function<void(nlohmann::json*)>& edit) {
  const ZipReader in(from);
  ZipWriter out(to);
  for (const std::string& name : in.Names()) {
    std::string bytes = in.Read(name);
    if (name == "manifest.json") {
      nlohmann::json manifest = nlohmann::json::parse(bytes);
      edit(&manifest);
      bytes = manifest.dump(1);
    }
    out.Add(name, std::move(bytes));
  }
  out.Close();
}

TEST(MapFile, RefusesDamagedForeignAndNewerFilesNamingThem) {
  const std::filesystem::path dir = testing::ScratchDir("map_file_bad");
  const std::filesystem::path good = dir / "good.dsmap";
  WriteMapFile(good, SampleFile());
  const std::string bytes = Bytes(good);
  const auto message = [](const std::filesystem::path& path) {
    return testing::MessageOf([&] { ReadMapFile(path); });
  };
  EXPECT_THAT(message(dir / "none.dsmap"), HasSubstr("none.dsmap: no such file"));
  EXPECT_THAT(message(dir), HasSubstr("not a file"));
  WriteBytes(dir / "empty.dsmap", "");
  EXPECT_THAT(message(dir / "empty.dsmap"), HasSubstr("empty.dsmap: not a readable zip archive"));
  WriteBytes(dir / "text.dsmap", "map: yes\n");
  EXPECT_THAT(message(dir / "text.dsmap"), HasSubstr("text.dsmap: not a readable zip archive"));
  WriteBytes(dir / "half.dsmap", bytes.substr(0, bytes.size() / 2));
  EXPECT_THAT(message(dir / "half.dsmap"), HasSubstr("half.dsmap: "));

  ZipWriter foreign(dir / "foreign.dsmap");
  foreign.Add("readme.txt", "not a map");
  foreign.Close();
  EXPECT_THAT(message(dir / "foreign.dsmap"), HasSubstr("foreign.dsmap: not a dsm map file (no manifest.json)"));

  using nlohmann::json;
  EditManifest(good, dir / "newer.dsmap", [](json* m) { (*m)["version"] = 2; });
  EXPECT_THAT(message(dir / "newer.dsmap"), HasSubstr("newer.dsmap: format version 2 (written by dsm test)"));
  EditManifest(good, dir / "other.dsmap", [](json* m) { (*m)["format"] = "orb-atlas"; });
  EXPECT_THAT(message(dir / "other.dsmap"), HasSubstr("other.dsmap: not a dsm map file"));
  EditManifest(good, dir / "shape.dsmap", [](json* m) { (*m)["maps"][0]["keyframes"] = 5; });
  EXPECT_THAT(message(dir / "shape.dsmap"), HasSubstr("shape.dsmap: array maps/0/keyframe_time has the wrong shape"));
  EditManifest(good, dir / "crc.dsmap", [](json* m) {
    json& crc = (*m)["arrays"]["maps/0/point_idepth"]["crc32"];
    crc = crc.get<uint32_t>() ^ 1u;
  });
  EXPECT_THAT(message(dir / "crc.dsmap"), HasSubstr("crc.dsmap: array maps/0/point_idepth is damaged (CRC)"));
  EditManifest(good, dir / "missing.dsmap", [](json* m) { (*m)["arrays"].erase("maps/0/point_host"); });
  EXPECT_THAT(message(dir / "missing.dsmap"), HasSubstr("arrays.maps/0/point_host is missing from the manifest"));
  EditManifest(good, dir / "window.dsmap", [](json* m) { (*m)["maps"][0]["window"][0] = 9; });
  EXPECT_THAT(message(dir / "window.dsmap"), HasSubstr("maps[0].window holds an id outside the map's 4 keyframes"));
}

// Every flipped byte either leaves the file readable as it was (a byte the zip format does not
// check, as an entry's date in its local header) or makes the reader refuse it: never a crash,
// never a different map.
TEST(MapFile, AFlippedByteIsRefusedOrHarmless) {
  const std::filesystem::path dir = testing::ScratchDir("map_file_flipped");
  const MapFile file = SampleFile();
  WriteMapFile(dir / "good.dsmap", file);
  const std::string bytes = Bytes(dir / "good.dsmap");
  int refused = 0, harmless = 0;
  for (size_t at = 7; at < bytes.size(); at += bytes.size() / 97) {
    std::string flipped = bytes;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x5a);
    WriteBytes(dir / "flipped.dsmap", flipped);
    try {
      const MapFile read = ReadMapFile(dir / "flipped.dsmap");
      ExpectSameMaps(file, read);
      ++harmless;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("flipped.dsmap")) << "byte " << at;
      ++refused;
    }
  }
  EXPECT_GT(refused, 80);
  std::printf("flipped bytes: %d refused, %d harmless\n", refused, harmless);
}

}  // namespace
}  // namespace dsm
