// SPDX-License-Identifier: MIT
// The Atlas: every map of a run (the current one, those set aside, those merged into another and
// those loaded from a map file) and which one takes each frame, for the command line's run
// (run/dataset_run.h) and the Python System alike.
//
// The current map takes the frames. When relocalisation keeps failing in it (System::NeedsNewMap)
// a new map starts and the old one is suspended (System::Suspend), not ended: while the current
// map is not tracking (initialising or lost), every frame is also tried against the suspended
// maps, newest first. A suspended map's relocalisation is tentative until the next frame confirms
// it, so the frame it relocalised waits (the current map has not seen it): confirmed, both frames
// are the suspended map's, it becomes the current map again (the camera is back where it was
// mapped) and the map it replaces ends; withdrawn, the current map takes both frames in order.
// Each frame thus belongs to exactly one map, and a map's frames may come in several spans.
// While the current map tracks, its new keyframes are compared with the suspended maps this run
// made (the merge candidates of the Atlas's place index, atlas_places.h: place recognition and
// verification on its mapping side); when
// one is recognised, the current map takes it in (System::MergeVerified) and the two go on as one,
// under the smaller of their ids (the first map's output folder keeps the whole trajectory); the
// map taken in ends without frames or keyframes of its own (Closer's `merged_into`). A suspended
// map is used by this thread only after the current map's mapping side has finished (Finish).
// Maps loaded from a map file (System::RestoreMap) start as suspended maps, before the first new
// one: the camera is taken to be in one of them as soon as it relocalises there. Until it has been
// in one, they are tried while the current map is young too (System::Young): a map started where
// the camera is in a known place gives way to the loaded one (the run's first relocalisation there
// takes a few frames, and the initialiser may be quicker, above all when frames are dropped).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "dsm/image/image.h"
#include "dsm/system/atlas_places.h"
#include "dsm/system/system.h"

namespace dsm {

class Atlas {
 public:
  // Spans of frames (first, last) a map took, in order.
  using Spans = std::vector<std::pair<int, int>>;
  using Factory = std::function<std::unique_ptr<System>()>;
  // Called once per map when it ends for good (replaced by a resumed map, or at Close), with its
  // id (creation order, from 0; a merge gives the smaller id to the map that goes on) and spans
  // (empty: it took no frame, or its frames went with a merge); `merged_into`: the map that took
  // it in (-1: none).
  using Closer = std::function<void(int id, System& system, const Spans& spans, int merged_into)>;
  // `loaded`: the maps of a map file, each taken up by a System of `make` (System::RestoreMap, as
  // `use` says) and suspended, with ids 0, 1, ...; the first new map takes the next id.
  Atlas(Factory make, Closer close, std::vector<StoredMap> loaded = {},
        System::LoadedMapUse use = System::LoadedMapUse::kExtend);

  // A frame the run settled: its report and the map it belongs to.
  struct Settled {
    FrameReport report;
    int map = 0;
  };
  // Hands frame `index` to the maps; returns the frames settled by it, in order: none when it
  // waits for the next frame to confirm a suspended map, two when a waiting frame is settled too.
  std::vector<Settled> Process(int index, int64_t t_ns, const Image<float>& image, double exposure_ms,
                               std::optional<std::chrono::steady_clock::time_point> wait_until);
  // The current map takes a frame still waiting (the run ends or stops; the suspended map that
  // relocalised it withdraws that); its report, if any.
  std::vector<Settled> Flush();
  // Suspends the current map and starts a new one.
  void StartNewMap();
  // Ends every map (Closer), suspended ones included, in creation order.
  void Close();

  System& current() { return *current_.system; }
  // The map with this id while the atlas holds it, current or suspended (null: ended, merged into
  // another, or never made).
  const System* Find(int id) const;
  int current_id() const { return current_.id; }
  int loaded_maps() const { return loaded_; }  // Taken up from a map file: ids 0 .. loaded_maps() - 1.
  // Whether `system`, one of these maps, goes into a map file saved at the end: localising in the
  // loaded maps, a new map started outside them does not (the file keeps the loaded maps alone).
  bool SavedInMapFile(const System& system) const {
    return use_ != System::LoadedMapUse::kLocalize || system.localizing();
  }

 private:
  struct Entry {
    int id = 0;
    std::unique_ptr<System> system;
    Spans spans;
    bool open = false;  // Its last span is still growing (it is the current map).
    int merged_into = -1;
  };
  struct Waiting {
    int index = -1;
    int64_t t_ns = 0;
    Image<float> image;
    double exposure_ms = 0.0;
    FrameReport report;  // The suspended map's.
    size_t suspended = 0;  // Which one (suspended_ index).
  };
  Entry NewEntry();
  Settled TakeCurrent(int index, int64_t t_ns, const Image<float>& image, double exposure_ms,
                      std::optional<std::chrono::steady_clock::time_point> wait_until);
  static void Note(Entry* e, int index);
  // The current map's merge candidates: the suspended maps this run made.
  void SetMergeCandidates();
  // The suspended map the current one recognised, taken in (System::MergeVerified) when ready.
  void MergeIfReady();

  Factory make_;
  Closer close_;
  AtlasPlaces places_;  // Every map's places (declared before the maps: they leave it when destroyed).
  System::LoadedMapUse use_;
  int next_id_ = 0;
  Entry current_;
  std::vector<Entry> suspended_;  // Oldest first.
  std::vector<Entry> merged_;     // Taken in by another map; ended at Close.
  TrackingStatus current_status_ = TrackingStatus::kInitializing;  // Of its last frame.
  int loaded_ = 0;              // Maps loaded from a map file (ids 0 .. loaded_ - 1).
  bool in_loaded_map_ = false;  // The camera has been in one of them.
  // Whether the suspended maps are tried for this frame.
  bool TrySuspended() const;
  std::optional<Waiting> waiting_;
};

}  // namespace dsm
