// SPDX-License-Identifier: MIT
// Lost frames and relocalisation end to end.
//   `loop` with the defects of a bad recording (15 black frames, 15 of noise, a corrupt file, a
//   hand over the lens for 41 frames): the run ends normally in one map, the defects cost their
//   frames only (defect_checks.h: each caught, relocalised within 5 frames, no keyframe made of
//   them, every later frame tracked); the keyframe ATE stays within 1.5x the clean run's.
//   The same at 320x240 over 160 frames (DefectsAtLowResolution). A plainer view after the defect
//   (PlainerViewAfterTheDefect). A right pose whose guess the coarse energy ranks low, with turned
//   textures (TheRightGuessRankedLow), and the seam it leaves adjusted (TheSeamIsAdjusted). A
//   relocalised pose a few percent off: the part mapped from it is moved onto the old map when
//   the lap closes (ThePartIsRejoined).
//   Noise and a hand right after the start (BadFramesRightAfterTheStart).
//   A fast `orbit` that loses two frames and skips three: tracking resumes where the camera went
//   (ShortLossThenSkippedFrames); frames missing from the recording count by their timestamps
//   (GapInTheRecording).
//   `loop` spliced onto `forward` (the camera reappears in a corridor it never saw): relocalisation
//   keeps failing, a second map starts, and each map writes and evaluates its own trajectories;
//   spliced back onto `loop` (the camera returns), the first map resumes; after only 10 frames of
//   `loop`, the young map is given up sooner (AYoungMapIsGivenUpSooner).
//   `forward` with 70 frames cut out (the camera reappears beyond all it mapped): a second map,
//   never a relocalisation into the first, which takes the first in when the camera walks back
//   (ALongCutStartsASecondMapThatJoinsTheFirst).
//   A System fed frame by frame through black frames goes through every transition of its
//   tracking state (EveryTrackingStateIsReached).
#include <fstream>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "dsm/io/trajectory_io.h"
#include "dsm/run/defect_checks.h"
#include "dsm/run/frame_reader.h"
#include "dsm/run/run.h"
#include "dsm/system/system.h"
#include "dsm/synth/sequence_writer.h"
#include "dsm/testing/test_data.h"

namespace dsm {
namespace {

namespace fs = std::filesystem;
using testing::ExpectDefectsCostTheirFramesOnly;
using testing::TumStamps;

fs::path Render(const std::string& scene, int frames, const std::string& defects, const std::string& name,
                int width = 0, int height = 0, bool turned_textures = false, uint32_t seed = 1) {
  synth::SynthOptions options;
  options.scene = scene;
  options.seed = seed;
  options.frames = frames;
  options.defects = defects;
  options.turned_textures = turned_textures;
  if (width > 0) options.width = width, options.height = height;
  const fs::path dir = testing::ScratchDir("reloc_" + name) / "sequence";
  synth::WriteSequence(synth::MakeSequence(options), options, dir);
  return dir;
}

RunSummary RunSequential(const fs::path& dir, const fs::path& out, int end = -1,
                         const RelocalisationOptions& relocalisation = {}) {
  RunOptions options;
  options.pace = Pace::kSequential;
  options.quiet = true;
  options.end = end;
  options.system.relocalisation = relocalisation;
  return RunDataset(OpenDataset(dir), options, out);
}

double KeyframeAte(const RunSummary& s) { return (*s.eval)["keyframes"]["ape"]["rmse"].get<double>(); }

// `scene` rendered clean and with `defects` (at width x height when given), each run
// sequentially: the defects cost their frames only (defect_checks.h), and the keyframe ATE stays
// within `max_ate_ratio` of the clean run's. Returns the damaged run.
RunSummary ExpectDefectRunLikeTheClean(const std::string& scene, int frames, const std::string& defects,
                                       const std::vector<testing::DefectRange>& ranges, double max_ate_ratio,
                                       const std::string& name, int width = 0, int height = 0,
                                       bool turned_textures = false, uint32_t seed = 1) {
  const fs::path clean = Render(scene, frames, "", name + "_clean", width, height, turned_textures, seed);
  const fs::path bad = Render(scene, frames, defects, name + "_defects", width, height, turned_textures, seed);
  const RunSummary c = RunSequential(clean, clean.parent_path() / "out");
  const fs::path out = bad.parent_path() / "out";
  const RunSummary s = RunSequential(bad, out);
  std::printf("clean: %s\nwith defects: %s\n", c.line.c_str(), s.line.c_str());
  ExpectDefectsCostTheirFramesOnly(OpenDataset(bad), s, out, ranges, name);
  EXPECT_TRUE(s.eval && c.eval);
  if (s.eval && c.eval) {
    EXPECT_LE(KeyframeAte(s), max_ate_ratio * KeyframeAte(c));
  }
  return s;
}

TEST(Relocalisation, DefectsCostTheirFramesOnly) {
  // The part mapped after each relocalisation joins the map as it was: the loop adjustment after a
  // relocalisation (SystemOptions::loop_ba_after_relocalisation) keeps the ATE within 1.5x.
  const RunSummary s = ExpectDefectRunLikeTheClean("loop", 0, "black:200-214,noise:300-314,corrupt:350,cover:400-440",
                                                   {{200, 214}, {300, 314}, {400, 440, true}}, 1.5, "loop");
  EXPECT_EQ(s.stats["frames_skipped"], 1);
}

// 160 frames of `loop` at 320x240 with the same kinds of defect. Two traps: the right guesses
// (the camera turned 15 deg under the hand) turn much of the map out of view, so their coarse
// energy must be scored on the points still in view or a look-alike pose 75 deg off, at 1.9x the
// usual residual, wins; and a frame with the hand half off the lens must not relocalise to a
// degenerate pose. Frame 111, the hand over 55% of the view, must not become a keyframe tracked
// from the rest: its texture falls to 0.65x frame 110's.
TEST(Relocalisation, DefectsAtLowResolution) {
  ExpectDefectRunLikeTheClean("loop", 160, "black:60-66,noise:80-84,corrupt:90,cover:110-125",
                              {{60, 66}, {80, 84}, {110, 125, true}}, 3.0, "small_loop", 320, 240);
}

// Bad frames right after the start (`loop` at 320x240 starts at frame 5): the quality test's
// levels are seeded from the initialiser's frames and the second keyframe's neighbour, so noise
// from frame 7 on is lost like any other. Levels that judge only after many trusted frames let
// noise frame 7 be tracked and become a keyframe, and the map breaks from there.
// Every transition of tracking_state.h, as a System fed a rendering with black frames goes through
// them: the start, tracking, black frames lost, the relocalisation after them and its
// confirmation; and, where the run is told to withdraw its first relocalisation (as at the end of
// a run: System::WithdrawTentative), lost again until the next one is confirmed. The state agrees
// with each frame's report.
TEST(Relocalisation, EveryTrackingStateIsReached) {
  const fs::path dir = Render("loop", 90, "black:50-56", "states", 320, 240);
  const Dataset dataset = OpenDataset(dir);
  const SystemOptions options;
  const Undistorter undistorter = FrameUndistorter(dataset, options);
  std::set<std::pair<TrackingState, TrackingState>> seen;
  for (const bool withdraw_first : {false, true}) {
    System system(undistorter.output(), options);
    bool withdrawn = false;
    int confirmed_at = -1;
    for (int i = 0; i < static_cast<int>(dataset.size()); ++i) {
      const FrameOrError frame = TryReadFrame(dataset, undistorter, i);
      ASSERT_TRUE(frame.error.empty()) << frame.error;
      const TrackingState before = system.state();
      const FrameReport r = system.Process(i, dataset.frames[i].t_ns, frame.image, 0.0);
      const TrackingState after = system.state();
      seen.insert({before, after});
      if (after == TrackingState::kInitializing) {
        EXPECT_EQ(r.status, TrackingStatus::kInitializing) << i;
      } else if (after == TrackingState::kLost) {
        EXPECT_EQ(r.status, TrackingStatus::kLost) << i;
      } else {
        EXPECT_EQ(r.status, TrackingStatus::kOk) << i;
        EXPECT_EQ(r.relocalised, after == TrackingState::kConfirming) << i;
      }
      if (i >= 50 && i <= 56) {
        EXPECT_EQ(after, TrackingState::kLost) << i;
      }
      if (after == TrackingState::kConfirming && withdraw_first && !withdrawn) {
        system.WithdrawTentative();
        withdrawn = true;
        seen.insert({after, system.state()});
        EXPECT_EQ(system.state(), TrackingState::kLost);
      }
      if (before == TrackingState::kConfirming && after == TrackingState::kTracking && confirmed_at < 0) confirmed_at = i;
    }
    system.Finish();
    EXPECT_EQ(system.state(), TrackingState::kTracking);
    EXPECT_GT(confirmed_at, 57);
    EXPECT_LE(confirmed_at, 57 + 5 + (withdraw_first ? 2 : 0));
    EXPECT_EQ(system.stats().relocalisations, 1);
    EXPECT_EQ(withdrawn, withdraw_first);
  }
  using S = TrackingState;
  for (const auto& t : std::vector<std::pair<S, S>>{{S::kInitializing, S::kTracking},
                                                    {S::kTracking, S::kTracking},
                                                    {S::kTracking, S::kLost},
                                                    {S::kLost, S::kLost},
                                                    {S::kLost, S::kConfirming},
                                                    {S::kConfirming, S::kTracking},
                                                    {S::kConfirming, S::kLost}}) {
    EXPECT_TRUE(seen.count(t)) << TrackingStateName(t.first) << " -> " << TrackingStateName(t.second);
  }
  // Never in one frame: a lost frame goes back to tracking only through a confirmation, and a
  // frame that fails while tracking is lost before it is tried against the map.
  EXPECT_FALSE(seen.count({S::kLost, S::kTracking}));
  EXPECT_FALSE(seen.count({S::kTracking, S::kConfirming}));
}

TEST(Relocalisation, BadFramesRightAfterTheStart) {
  const RunSummary s = ExpectDefectRunLikeTheClean("loop", 160, "noise:7-14,cover:40-60", {{7, 14}, {40, 60, true}},
                                                   2.0, "start_loop", 320, 240);
  EXPECT_EQ(s.stats["initialized_at_frame"], 5);
}

// `rotation` with 15 frames of noise: after them the camera looks at a plainer part of the room,
// 0.6 of the usual texture. Such a frame may also be a hand half over the lens, so it relocalises
// only by three sightings that move as one camera; not tried at all, the first map is given up 30
// frames after the loss and a second one starts.
TEST(Relocalisation, PlainerViewAfterTheDefect) {
  ExpectDefectRunLikeTheClean("rotation", 240, "noise:180-194", {{180, 194}}, 1.5, "rotation");
}

// 240 frames of `loop` with turned textures (synth::Texture::turned) and 15 black frames. After
// them the camera has turned 20 deg and moved 0.64 m from the last keyframe, about a fifth of its
// points in view. Of the reference's 16 guesses the coarse energy ranks the motion's prediction
// turned by 0.05 rad 4th (1.4 against 1.2); the two lowest end at 4.2-4.6x the residual level
// when refined. When nothing relocalises the frame, the reference's other guesses are refined
// too: that one ends at 1.04x, and frames 215-217 relocalise (with only the two best ranked
// refined, every frame fails and the first map is given up).
TEST(Relocalisation, TheRightGuessRankedLow) {
  ExpectDefectRunLikeTheClean("loop", 240, "black:200-214", {{200, 214}}, 1.5, "turned_loop", 0, 0,
                              /*turned_textures=*/true);
}

// Seed 3 of the same: frame 217 relocalises 2-3 mm off, and the window, which frees the keyframes
// before the loss as well, bends those towards it. The keyframes from 8 before the loss on are
// adjusted together every second keyframe of the first 8 after it, held by the older ones whose
// points they see (SystemOptions::seam_ba_count), so that the part after the loss does not stay
// off.
TEST(Relocalisation, TheSeamIsAdjusted) {
  const RunSummary s = ExpectDefectRunLikeTheClean("loop", 240, "black:200-214", {{200, 214}}, 1.5, "turned_loop_seed3",
                                                   0, 0, /*turned_textures=*/true, /*seed=*/3);
  int seams = 0;
  for (const auto& k : s.stats["per_keyframe"]) seams += k.contains("loop_ba") && k["loop_ba"]["seam"].get<bool>();
  EXPECT_GE(seams, 2);
}

// `loop` seed 2 with 15 black frames: after them the camera is 0.75 m and 27 deg from the last
// keyframe, with 5-12% of its points in view. A frame's alignment may keep as little as
// tracker.min_usage (4%) of the points in view, and each lost frame is also aligned from the
// sightings of the frames before it: 215 and 216 are sighted (lost too long to predict), 217
// moves as one camera with them and relocalises. The part mapped from so few points runs high in
// scale, which one adjustment after the relocalisation does not remove: the map is adjusted
// periodically once it has been relocalised.
TEST(Relocalisation, MostOfTheMapOutOfView) {
  ExpectDefectRunLikeTheClean("loop", 0, "black:200-214", {{200, 214}}, 1.5, "loop_seed2", 0, 0,
                              /*turned_textures=*/false, /*seed=*/2);
}

// `exposure` seed 2 with 15 black frames: as `loop` seed 2 above, frame 217 relocalises with few
// of the keyframe's points in view, but 21-30 mm off (a shift along the image traded for a turn
// about its other axis), and the part mapped from it carries the offset whole. When the lap
// closes (frame 278) the old map's points are outliers in the new keyframes: the keyframe is
// aligned with the old keyframe and the part moved onto the old map (rejoin_min_outliers), once,
// where otherwise it goes on beside the old map. The part keeps a distortion about the loss
// (about 1 mm where the clean run is 0.4) that the loop adjustments of the second lap hold as the
// old map, so the run stays within 2x the clean one, not 1.5x.
TEST(Relocalisation, ThePartIsRejoined) {
  const RunSummary s = ExpectDefectRunLikeTheClean("exposure", 0, "black:200-214", {{200, 214}}, 2.0, "exposure_seed2",
                                                   0, 0, /*turned_textures=*/false, /*seed=*/2);
  int rejoined = 0;
  for (const auto& k : s.stats["per_keyframe"]) rejoined += k.contains("rejoin");
  EXPECT_EQ(rejoined, 1);
}

// `orbit` in 150 frames (four times its speed: ~0.1 m a frame, a near occluder passing): two black
// frames, then three unreadable files. Frame 82 relocalises right; frame 86 is tracked from it
// four frames later, from the camera's motion through the loss: from frame 82's pose (the
// velocity reset) the alignment ends in a wrong minimum that passes the residual level the
// relocalisation has just restarted, and the keyframe made from it breaks the map. As in
// --realtime on the full `orbit`: lost for two frames where the occluder passes, relocalised,
// then frames dropped.
TEST(Relocalisation, ShortLossThenSkippedFrames) {
  const fs::path bad = Render("orbit", 150, "black:80-81,corrupt:83-85", "fast_orbit");
  const fs::path out = bad.parent_path() / "out";
  const RunSummary s = RunSequential(bad, out);
  std::printf("%s\n", s.line.c_str());
  EXPECT_EQ(s.stats["frames_skipped"], 3);
  EXPECT_EQ(s.stats["maps"].size(), 1u);
  ASSERT_TRUE(s.eval);
  EXPECT_LT(KeyframeAte(s), 0.005);
  // Tracking goes on from the first frame after the skipped ones (the occluder costs frame 99 later).
  const Dataset d = OpenDataset(bad);
  const std::set<int64_t> posed = TumStamps(out / "frames.tum");
  for (size_t i = 86; i < 96; ++i) EXPECT_TRUE(posed.count(d.frames[i].t_ns)) << "frame " << i;
}

// The same fast `orbit` with four frames missing from the recording (synth --defects cut:83-86:
// the timestamps jump by five frame intervals). The motion model counts the intervals, not the
// frames: the first frame after the gap is tracked from the camera's motion over five intervals.
// Counted per frame, it would be guessed one interval on and fail, and the frames after it be lost
// until a relocalisation.
TEST(Relocalisation, GapInTheRecording) {
  const fs::path dir = Render("orbit", 150, "cut:83-86", "orbit_gap");
  const Dataset d = OpenDataset(dir);
  ASSERT_EQ(d.size(), 146u);
  const fs::path out = dir.parent_path() / "out";
  const RunSummary s = RunSequential(dir, out);
  std::printf("%s\n", s.line.c_str());
  EXPECT_EQ(s.stats["maps"].size(), 1u);
  for (const auto& episode : s.stats["lost_episodes"]) {
    EXPECT_FALSE(episode[0].get<int>() <= 85 && episode[1].get<int>() >= 83) << episode;
  }
  const std::set<int64_t> posed = TumStamps(out / "frames.tum");
  for (size_t i = 83; i < 90; ++i) EXPECT_TRUE(posed.count(d.frames[i].t_ns)) << "frame " << i;
  ASSERT_TRUE(s.eval);
  EXPECT_LT(KeyframeAte(s), 0.005);
}

// A dataset of `pieces` (a dataset, its first frame, one past its last) one after another, each
// 50 ms after the one before, with their ground truth: one folder dataset. Returns the first frame
// index of each piece in it.
std::vector<int> Splice(const std::vector<std::tuple<const Dataset*, int, int>>& pieces, const fs::path& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir / "images");
  fs::copy_file(std::get<0>(pieces.front())->root / "camera.yaml", dir / "camera.yaml");
  Trajectory gt;
  std::ofstream times(dir / "times.txt");
  std::vector<int> starts;
  int n = 0;
  int64_t last = 0;
  for (const auto& [d, first, end] : pieces) {
    starts.push_back(n);
    const int64_t shift = n == 0 ? 0 : last + 50000000 - d->frames[first].t_ns;
    for (int i = first; i < end; ++i, ++n) {
      char name[32];
      std::snprintf(name, sizeof(name), "%06d.png", n);
      fs::create_symlink(d->root / "images" / d->frames[i].image, dir / "images" / name);
      last = d->frames[i].t_ns + shift;
      times << last << " " << d->frames[i].exposure_ms << "\n";
      gt.Add(last, d->ground_truth.poses[i]);
    }
  }
  times.close();
  WriteTumTrajectory(dir / "groundtruth.tum", gt);
  return starts;
}

// 100 frames of `loop`, then 150 of `forward` (the camera reappears in a corridor it never saw):
// relocalisation keeps failing, a second map starts, and each map writes and evaluates its own
// trajectories.
TEST(Relocalisation, ANewPlaceStartsASecondMap) {
  const fs::path room = Render("loop", 100, "", "splice_room"), corridor = Render("forward", 150, "", "splice_corridor");
  const Dataset a = OpenDataset(room), b = OpenDataset(corridor);
  const fs::path dir = testing::ScratchDir("reloc_splice") / "sequence";
  Splice({{&a, 0, 100}, {&b, 0, 150}}, dir);
  const fs::path out = dir.parent_path() / "out";
  const RunSummary s = RunSequential(dir, out);
  std::printf("%s\n", s.line.c_str());
  ASSERT_EQ(s.stats["maps"].size(), 2u);
  const auto& second = s.stats["maps"][1];
  EXPECT_EQ(second["dir"], "map_1");
  EXPECT_GE(second["first_frame"].get<int>(), 101);
  EXPECT_LE(second["first_frame"].get<int>(), 140);
  EXPECT_EQ(s.stats["relocalisations"], 0);
  for (const fs::path& m : {out, out / "map_1"}) {
    EXPECT_TRUE(fs::exists(m / "keyframes.tum")) << m;
    EXPECT_TRUE(fs::exists(m / "frames.tum")) << m;
    EXPECT_TRUE(fs::exists(m / "eval.json")) << m;
  }
  // Each map on its own: poses of its own frames only, accurate after its own alignment.
  const int64_t corridor_start = OpenDataset(dir).frames[100].t_ns;
  EXPECT_LT(*std::prev(TumStamps(out / "frames.tum").end()), corridor_start);
  EXPECT_GT(*TumStamps(out / "map_1" / "frames.tum").begin(), a.frames.back().t_ns);
  for (const auto& m : s.stats["maps"]) EXPECT_LT(m["keyframe_ate_m"].get<double>(), 0.005);
}

// A map of its first keyframes only, lost for good: 10 frames of `loop`, then the corridor. The
// young map is given up after relocalisation.max_predicted_frames failed frames, not
// max_lost_frames (the EuRoC frames with black frames 5-20: the second map started at frame 50,
// now at 30).
TEST(Relocalisation, AYoungMapIsGivenUpSooner) {
  const fs::path room = Render("loop", 10, "", "young_room"), corridor = Render("forward", 80, "", "young_corridor");
  const Dataset a = OpenDataset(room), b = OpenDataset(corridor);
  const fs::path dir = testing::ScratchDir("reloc_young") / "sequence";
  Splice({{&a, 0, 10}, {&b, 0, 80}}, dir);
  RelocalisationOptions options;
  for (const int young : {options.young_map_frames, 0}) {
    options.young_map_frames = young;
    const RunSummary s = RunSequential(dir, dir.parent_path() / ("out_" + std::to_string(young)), -1, options);
    std::printf("young_map_frames %d: %s\n", young, s.line.c_str());
    ASSERT_EQ(s.stats["maps"].size(), 2u);
    const auto& first = s.stats["maps"][0];
    const int second = s.stats["maps"][1]["first_frame"].get<int>();
    ASSERT_LE(first["frames_tracked"].get<int>(), RelocalisationOptions{}.young_map_frames);
    // Every corridor frame with texture is tried: the new map starts right after the limit.
    const int limit = young > 0 ? options.max_predicted_frames : options.max_lost_frames;
    EXPECT_GE(second, 10 + limit);
    EXPECT_LE(second, 10 + limit + 2);
    EXPECT_LT(s.stats["maps"][1]["keyframe_ate_m"].get<double>(), 0.005);
  }
}

// The camera leaves for the corridor and comes back: 100 frames of `loop`, 90 of `forward`, then
// `loop` again from frame 100. The first map is suspended while the second is made, not ended:
// the lost frames of the second are tried against it, and it takes the frames from the return on
// (atlas.h), where a third map would otherwise start.
TEST(Relocalisation, ReturnResumesTheFirstMap) {
  const fs::path room = Render("loop", 200, "", "return_room"), corridor = Render("forward", 90, "", "return_corridor");
  const Dataset a = OpenDataset(room), b = OpenDataset(corridor);
  const fs::path dir = testing::ScratchDir("reloc_return") / "sequence";
  const std::vector<int> starts = Splice({{&a, 0, 100}, {&b, 0, 90}, {&a, 100, 200}}, dir);
  const fs::path out = dir.parent_path() / "out";
  const RunSummary s = RunSequential(dir, out);
  std::printf("%s\n", s.line.c_str());
  ASSERT_EQ(s.stats["maps"].size(), 2u);
  const auto& first = s.stats["maps"][0];
  const auto& second = s.stats["maps"][1];
  // Every frame belongs to one map: the spans tile the run.
  EXPECT_EQ(s.stats["frames"], 290);
  ASSERT_EQ(first["spans"].size(), 2u);
  ASSERT_EQ(second["spans"].size(), 1u);
  EXPECT_EQ(first["spans"][0][0], 0);
  EXPECT_EQ(second["spans"][0][0].get<int>(), first["spans"][0][1].get<int>() + 1);
  EXPECT_EQ(first["spans"][1][0].get<int>(), second["spans"][0][1].get<int>() + 1);
  EXPECT_EQ(first["spans"][1][1], 289);
  // Back within 5 frames of the return, and tracked from there on in the first map's scale.
  EXPECT_GE(first["spans"][1][0].get<int>(), starts[2]);
  EXPECT_LE(first["spans"][1][0].get<int>(), starts[2] + 5);
  EXPECT_GE(s.stats["relocalisations"].get<int>(), 1);
  const Dataset d = OpenDataset(dir);
  const std::set<int64_t> posed = TumStamps(out / "frames.tum");
  const int back = first["spans"][1][0].get<int>();
  for (int i = back; i < 290; ++i) EXPECT_TRUE(posed.count(d.frames[i].t_ns)) << "frame " << i;
  for (const auto& m : s.stats["maps"]) EXPECT_LT(m["keyframe_ate_m"].get<double>(), 0.005);

  // The run ends on the frame the first map relocalised, before the next could confirm it: the
  // frame is the second map's, and the first map keeps no trace of it.
  const RunSummary cut = RunSequential(dir, out.parent_path() / "out_cut", back + 1);
  ASSERT_EQ(cut.stats["maps"].size(), 2u);
  EXPECT_EQ(cut.stats["frames"], back + 1);
  EXPECT_EQ(cut.stats["maps"][0]["spans"].size(), 1u);
  EXPECT_EQ(cut.stats["maps"][1]["spans"][0][1], back);
  EXPECT_FALSE(TumStamps(out.parent_path() / "out_cut" / "frames.tum").count(d.frames[back].t_ns));
}

// A sequence that leaves the mapped area and comes back: `forward` with frames 60-129 cut out, so
// the camera reappears 5.6 m further down the corridor, beyond the map, then walks back to the
// start. Relocalisation keeps failing and a second map starts; a run that ends before the return
// keeps the two maps apart, each evaluated on its own. On the way back the second map recognises
// the first one's keyframes and takes it in (atlas.h, System::MergeVerified): one map, under the
// first map's folder, with both parts' keyframes and frames in time order, evaluated as one
// trajectory. The corridor's textures are turned (synth::Texture::turned): with the default ones,
// which repeat every 2 m along it, frames 61-63 relocalised 1.5 m behind the last trusted pose
// against keyframes that look alike, and the map broke (keyframe ATE 3.4 m).
TEST(Relocalisation, ALongCutStartsASecondMapThatJoinsTheFirst) {
  const fs::path dir = Render("forward", 0, "cut:60-129", "long_cut", 0, 0, /*turned_textures=*/true);
  const fs::path out = dir.parent_path() / "out";
  // Ended 8 m down the corridor, before the return.
  const RunSummary apart = RunSequential(dir, dir.parent_path() / "out_apart", 200);
  std::printf("%s\n", apart.line.c_str());
  ASSERT_EQ(apart.stats["maps"].size(), 2u);
  EXPECT_EQ(apart.stats["relocalisations"], 0);
  EXPECT_EQ(apart.stats["maps_merged"].size(), 0u);
  EXPECT_EQ(apart.stats["maps"][1]["dir"], "map_1");
  EXPECT_EQ(apart.stats["maps"][1]["spans"].size(), 1u);
  for (const fs::path& m : {dir.parent_path() / "out_apart", dir.parent_path() / "out_apart" / "map_1"}) {
    EXPECT_TRUE(fs::exists(m / "keyframes.tum")) << m;
    EXPECT_TRUE(fs::exists(m / "eval.json")) << m;
  }
  for (const auto& m : apart.stats["maps"]) EXPECT_LT(m["keyframe_ate_m"].get<double>(), 0.005);

  const RunSummary s = RunSequential(dir, out);
  std::printf("%s\n", s.line.c_str());
  ASSERT_EQ(s.stats["maps"].size(), 2u);
  ASSERT_EQ(s.stats["maps_merged"].size(), 1u);
  const auto& merge = s.stats["maps_merged"][0];
  const auto& whole = s.stats["maps"][0];
  EXPECT_EQ(merge["map"], 1);
  EXPECT_EQ(s.stats["maps"][1]["merged_into"], 0);
  EXPECT_TRUE(s.stats["maps"][1]["dir"].is_null());
  EXPECT_FALSE(fs::exists(out / "map_1"));
  // Merged on the way back (the camera passes 8 m at frame 200), with the first map whole.
  EXPECT_GT(merge["frame"].get<int>(), 200);
  EXPECT_EQ(merge["keyframes"], apart.stats["maps"][0]["keyframes"]);
  // Every frame is the one map's: its spans tile the run; its keyframes and frames are written in
  // time order, the first map's among them.
  ASSERT_EQ(whole["spans"].size(), 2u);
  EXPECT_EQ(whole["spans"][0][0], 0);
  EXPECT_EQ(whole["spans"][1][0].get<int>(), whole["spans"][0][1].get<int>() + 1);
  EXPECT_EQ(whole["spans"][1][1], 329);
  const Trajectory keyframes = ReadTrajectory(out / "keyframes.tum", TrajectoryFormat::kTum);
  const Trajectory frames = ReadTrajectory(out / "frames.tum", TrajectoryFormat::kTum);
  EXPECT_EQ(static_cast<int>(keyframes.size()), s.stats["keyframes"].get<int>());
  EXPECT_EQ(static_cast<int>(frames.size()), s.stats["frames_tracked"].get<int>());
  EXPECT_TRUE(std::is_sorted(keyframes.stamps_ns.begin(), keyframes.stamps_ns.end()));
  EXPECT_TRUE(std::is_sorted(frames.stamps_ns.begin(), frames.stamps_ns.end()));
  const Dataset d = OpenDataset(dir);
  const std::set<int64_t> posed(frames.stamps_ns.begin(), frames.stamps_ns.end());
  EXPECT_TRUE(posed.count(d.frames[40].t_ns));
  EXPECT_TRUE(posed.count(d.frames[300].t_ns));
  // One alignment for both parts.
  EXPECT_LT(KeyframeAte(s), 0.005);
}

}  // namespace
}  // namespace dsm
