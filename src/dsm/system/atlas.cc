// SPDX-License-Identifier: MIT
#include "dsm/system/atlas.h"

#include <algorithm>

namespace dsm {

Atlas::Atlas(Factory make, Closer close, std::vector<StoredMap> loaded, System::LoadedMapUse use)
    : make_(std::move(make)), close_(std::move(close)), use_(use) {
  for (StoredMap& stored : loaded) {
    Entry e;
    e.id = next_id_++;
    e.system = make_();
    e.system->JoinPlaces(&places_);
    e.system->RestoreMap(std::move(stored), use);
    suspended_.push_back(std::move(e));
  }
  loaded_ = next_id_;
  current_ = NewEntry();
}

void Atlas::SetMergeCandidates() {
  std::vector<std::pair<int, PlaceMap*>> candidates;
  for (Entry& e : suspended_)
    if (e.id >= loaded_) candidates.emplace_back(e.id, e.system->place_map());
  places_.SetMergeCandidates(candidates);
}

void Atlas::MergeIfReady() {
  const int source = current_.system->MergeReady();
  if (source < 0 || waiting_) return;
  const auto it = std::find_if(suspended_.begin(), suspended_.end(), [&](const Entry& e) { return e.id == source; });
  if (it == suspended_.end() || !current_.system->MergeVerified(*it->system, std::max(source, current_.id))) return;
  Entry taken = std::move(*it);
  suspended_.erase(it);
  current_.spans.insert(current_.spans.end(), taken.spans.begin(), taken.spans.end());
  std::sort(current_.spans.begin(), current_.spans.end());
  taken.spans.clear();
  if (taken.id < current_.id) std::swap(taken.id, current_.id);
  taken.merged_into = current_.id;
  merged_.push_back(std::move(taken));
  SetMergeCandidates();
}

bool Atlas::TrySuspended() const {
  if (current_status_ != TrackingStatus::kOk) return true;
  return loaded_ > 0 && !in_loaded_map_ && current_.system->Young();
}

Atlas::Entry Atlas::NewEntry() {
  Entry e;
  e.id = next_id_++;
  e.system = make_();
  e.system->JoinPlaces(&places_);
  e.open = true;
  return e;
}

void Atlas::Note(Entry* e, int index) {
  if (e->spans.empty() || !e->open) e->spans.emplace_back(index, index);
  e->spans.back().second = index;
  e->open = true;
}

Atlas::Settled Atlas::TakeCurrent(int index, int64_t t_ns, const Image<float>& image, double exposure_ms,
                                    std::optional<std::chrono::steady_clock::time_point> wait_until) {
  Settled s{current_.system->Process(index, t_ns, image, exposure_ms, wait_until), current_.id};
  current_status_ = s.report.status;
  Note(&current_, index);
  return s;
}

std::vector<Atlas::Settled> Atlas::Process(int index, int64_t t_ns, const Image<float>& image, double exposure_ms,
                                             std::optional<std::chrono::steady_clock::time_point> wait_until) {
  std::vector<Settled> out;
  if (waiting_) {
    Waiting w = std::move(*waiting_);
    waiting_.reset();
    Entry& back = suspended_[w.suspended];
    FrameReport r = back.system->Process(index, t_ns, image, exposure_ms, wait_until);
    if (r.resumed) {
      // The camera is back in that map: it takes both frames and the frames after them.
      current_.open = false;
      close_(current_.id, *current_.system, current_.spans, -1);
      current_ = std::move(back);
      in_loaded_map_ = in_loaded_map_ || current_.id < loaded_;
      suspended_.erase(suspended_.begin() + static_cast<long>(w.suspended));
      Note(&current_, w.index);
      Note(&current_, index);
      current_status_ = r.status;
      SetMergeCandidates();
      out.push_back({w.report, current_.id});
      out.push_back({r, current_.id});
      return out;
    }
    // Withdrawn: the waiting frame is the current map's; this one too, unless that suspended map
    // relocalised it in turn.
    out.push_back(TakeCurrent(w.index, w.t_ns, w.image, w.exposure_ms, std::nullopt));
    if (r.relocalised) {
      waiting_ = Waiting{index, t_ns, image, exposure_ms, r, w.suspended};
      return out;
    }
    out.push_back(TakeCurrent(index, t_ns, image, exposure_ms, wait_until));
    return out;
  }
  if (TrySuspended()) {
    // The current map's mapping side may be reading the suspended maps it could merge.
    if (std::any_of(suspended_.begin(), suspended_.end(), [&](const Entry& e) { return e.id >= loaded_; }))
      current_.system->Finish();
    for (size_t k = suspended_.size(); k-- > 0;) {
      FrameReport r = suspended_[k].system->Process(index, t_ns, image, exposure_ms, wait_until);
      if (r.relocalised) {
        waiting_ = Waiting{index, t_ns, image, exposure_ms, r, k};
        return out;
      }
    }
  }
  out.push_back(TakeCurrent(index, t_ns, image, exposure_ms, wait_until));
  MergeIfReady();
  return out;
}

std::vector<Atlas::Settled> Atlas::Flush() {
  std::vector<Settled> out;
  if (!waiting_) return out;
  Waiting w = std::move(*waiting_);
  waiting_.reset();
  suspended_[w.suspended].system->WithdrawTentative();  // Unconfirmed: not that map's frame.
  out.push_back(TakeCurrent(w.index, w.t_ns, w.image, w.exposure_ms, std::nullopt));
  return out;
}

void Atlas::StartNewMap() {
  current_.system->Finish();  // Its mapping side is idle from here on (System::Suspend).
  current_.system->Suspend();
  current_.open = false;
  suspended_.push_back(std::move(current_));
  current_ = NewEntry();
  current_status_ = TrackingStatus::kInitializing;
  SetMergeCandidates();
}

const System* Atlas::Find(int id) const {
  if (current_.id == id) return current_.system.get();
  for (const Entry& e : suspended_)
    if (e.id == id) return e.system.get();
  return nullptr;
}

void Atlas::Close() {
  std::vector<Entry*> all = {&current_};
  for (Entry& e : suspended_) all.push_back(&e);
  for (Entry& e : merged_) all.push_back(&e);
  std::sort(all.begin(), all.end(), [](const Entry* a, const Entry* b) { return a->id < b->id; });
  for (Entry* e : all) {
    e->open = false;
    close_(e->id, *e->system, e->spans, e->merged_into);
    e->system.reset();
  }
  suspended_.clear();
  merged_.clear();
}

}  // namespace dsm
