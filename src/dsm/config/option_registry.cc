// SPDX-License-Identifier: MIT
#include "dsm/config/option_registry.h"

#include <charconv>
#include <concepts>
#include <functional>
#include <map>
#include <sstream>
#include <vector>

#include "dsm/io/yaml_file.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

// One option of a file: its key (section.name), how it is read from YAML, how its value is written
// back (so that reading it gives the same value), and what it means.
struct OptionEntry {
  std::string key;
  std::function<void(const YAML::Node&)> set;
  std::function<std::string()> get;
  std::string description;
};

// The shortest text that reads back as the same value.
template <std::floating_point T>
std::string Format(T v) {
  char text[32];
  const auto r = std::to_chars(text, text + sizeof(text), v);
  return std::string(text, r.ptr);
}
std::string Format(int v) { return std::to_string(v); }
std::string Format(bool v) { return v ? "true" : "false"; }
std::string Format(const std::string& v) { return v.empty() ? "\"\"" : v; }  // "" reads back as empty, not null.
std::string Format(const std::vector<int>& v) {
  std::string text = "[";
  for (size_t i = 0; i < v.size(); ++i) text += (i ? ", " : "") + std::to_string(v[i]);
  return text + "]";
}

template <typename T>
void Add(std::vector<OptionEntry>* e, std::string key, T* field, std::string description) {
  e->push_back({std::move(key), [field](const YAML::Node& n) { *field = n.as<T>(); },
                [field] { return Format(*field); }, std::move(description)});
}

// Every option in the order --print-config writes them; pointers into `*o`.
std::vector<OptionEntry> Entries(SystemOptions* o) {
  std::vector<OptionEntry> e;
  Add(&e, "system.pyramid_levels", &o->pyramid_levels,
      "Levels of the image pyramids; the undistorted image size is rounded to divide by 2^(levels - 1).");
  Add(&e, "system.max_initialization_frames", &o->max_initialization_frames,
      "Frames the initialiser tries against one first frame before it starts over.");
  Add(&e, "system.interpolation", &o->interpolation,
      "How residuals sample images: auto (cubic B-spline on noisy images, else bilinear) | bilinear | bspline.");
  Add(&e, "system.texture_loss_min_noise", &o->texture_loss_min_noise,
      "--mode dsm: the noise level (grey levels) from which the texture-loss test applies in the error models' fit (0: "
      "never).");
  Add(&e, "system.young_map_ba_first", &o->young_map_ba_first,
      "--mode dsm: the whole young map is bundle-adjusted at this many keyframes, then at twice as many ...");
  Add(&e, "system.young_map_ba_last", &o->young_map_ba_last, "... up to this many keyframes (0: never).");
  Add(&e, "system.loop_ba_min_gap", &o->loop_ba_min_gap,
      "--mode dsm: a keyframe whose covisible keyframes reach this many keyframes back starts a loop bundle adjustment "
      "(0: off).");
  Add(&e, "system.loop_ba_after_relocalisation", &o->loop_ba_after_relocalisation,
      "The loop adjustment once after a relocalisation, and every this many keyframes from then on (0: never).");
  Add(&e, "system.loop_ba_max_keyframes", &o->loop_ba_max_keyframes,
      "The most keyframes a loop adjustment frees (the newest).");
  Add(&e, "system.loop_ba_max_iterations", &o->loop_ba_max_iterations,
      "LM iterations per level of a loop adjustment (0: as pba.max_iterations).");
  Add(&e, "system.seam_ba_count", &o->seam_ba_count, "Adjustments of the seam a relocalisation leaves (0: none) ...");
  Add(&e, "system.seam_ba_step", &o->seam_ba_step, "... one every this many keyframes after it ...");
  Add(&e, "system.seam_ba_before", &o->seam_ba_before,
      "... over this many keyframes before the loss and all after it.");
  Add(&e, "system.rejoin_min_outliers", &o->rejoin_min_outliers,
      "The part mapped after a relocalisation is moved onto the older map when a keyframe sees this many of its points "
      "as outliers (0: never).");
  Add(&e, "system.keyframe_culling", &o->keyframe_culling,
      "--mode dsm: a keyframe leaving the window whose view the map already covers is retired, its few points "
      "re-hosted (false: every keyframe stays).");
  Add(&e, "loop_closure.enabled", &o->loop_closure.enabled,
      "--mode dsm: places seen again are recognised and the loop closed (false: the map joins them only where "
      "re-observation reaches).");
  Add(&e, "loop_closure.consistent_keyframes", &o->loop_closure.consistent_keyframes,
      "Keyframes in a row that must find the same place before it is verified.");
  Add(&e, "loop_closure.min_inliers", &o->loop_closure.min_inliers,
      "ORB matches that must agree with the Sim(3) between the two views.");
  Add(&e, "loop_closure.vocabulary", &o->loop_closure.vocabulary,
      "Vocabulary file (dsm vocabulary); empty: the one built into dsm.");
  Add(&e, "initializer.min_parallax_deg", &o->initializer.min_parallax_deg,
      "Median parallax of the corners before two views start the map, degrees.");
  Add(&e, "initializer.planar_start", &o->initializer.planar_start,
      "Start from the homography when one plane fills the view.");
  Add(&e, "initializer.min_track_share", &o->initializer.min_track_share,
      "The initialiser starts over once fewer than this share of the first frame's corners are still tracked.");
  Add(&e, "tracker.levels", &o->tracker.levels, "Pyramid levels of the frame alignment, coarse to fine.");
  Add(&e, "tracker.iterations", &o->tracker.iterations, "Gauss-Newton iterations per level, finest first.");
  Add(&e, "tracker.min_usage", &o->tracker.min_usage,
      "Tracking fails below this share of the reference's points in view.");
  Add(&e, "tracker.verified_reference", &o->tracker.verified_reference,
      "Track against the points whose observation in the keyframe the bundle adjustment verified (false: all that "
      "project).");
  Add(&e, "tracker.max_fit_samples", &o->tracker.robust.max_fit_samples,
      "The tracker's error model is fitted to at most this many residuals (evenly strided).");
  Add(&e, "candidates.target_count", &o->candidates.target_count, "Candidate points selected per keyframe.");
  Add(&e, "candidates.threshold_margin", &o->candidates.threshold_margin,
      "A candidate's gradient exceeds its block's median by this, grey levels.");
  Add(&e, "candidates.noise_factor", &o->candidates.noise_factor,
      "Gradient floor, in standard deviations of the image noise's gradient (0: none).");
  Add(&e, "candidates.contrast_factor", &o->candidates.contrast_factor,
      "Pattern contrast floor, in noise sigmas (0: none) ...");
  Add(&e, "activation.target_points", &o->activation.target_points, "Active points wanted in the window.");
  Add(&e, "keyframe.weight_parallax", &o->keyframe.weight_parallax,
      "Keyframe decision: weight of the parallax (translation over depth) ...");
  Add(&e, "keyframe.weight_visibility", &o->keyframe.weight_visibility, "... of the share of points out of view ...");
  Add(&e, "keyframe.weight_brightness", &o->keyframe.weight_brightness,
      "... and of the brightness change; a keyframe when their sum exceeds 1.");
  Add(&e, "quality.min_texture_ratio", &o->quality.min_texture_ratio,
      "A frame with less than this share of the usual texture is lost (black, covered).");
  Add(&e, "quality.min_relocalisation_texture_ratio", &o->quality.min_relocalisation_texture_ratio,
      "A lost frame with less relocalises only by three sightings that move as one camera.");
  Add(&e, "quality.max_residual_ratio", &o->quality.max_residual_ratio,
      "A frame whose median residual exceeds this multiple of the usual is lost.");
  Add(&e, "quality.max_rotation_deg", &o->quality.max_rotation_deg,
      "A frame that turned more than this from the last trusted one is lost, degrees per frame.");
  Add(&e, "quality.history", &o->quality.history, "Trusted frames the usual texture and residual are the medians of.");
  Add(&e, "relocalisation.candidates", &o->relocalisation.candidates,
      "Keyframes a lost frame is aligned with besides its reference.");
  Add(&e, "relocalisation.max_lost_frames", &o->relocalisation.max_lost_frames,
      "Failed relocalisations in a row before a new map starts (0: never).");
  Add(&e, "relocalisation.max_predicted_frames", &o->relocalisation.max_predicted_frames,
      "Lost frames during which the motion's prediction can accept a relocalisation (after: three sightings).");
  Add(&e, "relocalisation.young_map_frames", &o->relocalisation.young_map_frames,
      "A map that tracked at most this many frames is given up after max_predicted_frames failures.");
  Add(&e, "window.temporal_keyframes", &o->window.temporal_keyframes,
      "N_t: temporal keyframes of the window, the newest included.");
  Add(&e, "window.covisible_keyframes", &o->window.covisible_keyframes,
      "N_c: covisible old keyframes of the window (--mode dsm).");
  Add(&e, "window.optimize_covisible_poses", &o->window.optimize_covisible_poses,
      "Optimise the covisible keyframes' poses, as the paper does (false: held, their points optimised).");
  Add(&e, "window.depleted_distance_px", &o->window.depleted_distance_px,
      "Covisible keyframes are chosen for the pixels this far (pixels) from every point the window projects.");
  Add(&e, "occlusion.enabled", &o->occlusion.enabled,
      "A point hidden behind nearer map points gets no observation in a new keyframe.");
  Add(&e, "occlusion.depth_ratio", &o->occlusion.depth_ratio,
      "A point is nearer when its depth is below the other's over this ratio.");
  Add(&e, "pba.levels", &o->pba.levels, "N_p: pyramid levels of the bundle adjustment, coarse to fine.");
  Add(&e, "pba.max_iterations", &o->pba.max_iterations, "LM iterations per level.");
  Add(&e, "pba.initial_lambda", &o->pba.initial_lambda, "LM's starting damping.");
  Add(&e, "pba.min_camera_observations", &o->pba.min_camera_observations,
      "An active keyframe in fewer observations stays fixed.");
  Add(&e, "pba.min_link_ratio", &o->pba.min_link_ratio,
      "An active keyframe tied by less than this share of the observations that once placed it is held.");
  Add(&e, "pba.max_outside_observations", &o->pba.max_outside_observations,
      "Per point of a held keyframe: its newest observations outside the window that enter the problem.");
  Add(&e, "pba.max_outside_keyframes", &o->pba.max_outside_keyframes,
      "The most keyframes outside the window whose observations enter the problem (0: all).");
  Add(&e, "pba.max_sigma_ratio", &o->pba.max_sigma_ratio,
      "A keyframe's fitted error scale is bounded by this multiple of the problem's median (0: free).");
  Add(&e, "pba.refit_all_models", &o->pba.refit_all_models,
      "Refit every keyframe's error model in each adjustment (false: the newest only, as the original DSM).");
  Add(&e, "pba.max_rotation_step", &o->pba.max_rotation_step,
      "A level converges when the last step turns every pose by less than this (radians) ...");
  Add(&e, "pba.max_translation_step", &o->pba.max_translation_step,
      "... moves it by less than this (times the points' mean inverse depth) ...");
  Add(&e, "pba.max_a_step", &o->pba.max_a_step, "... changes every brightness parameter a by less than this ...");
  Add(&e, "pba.max_b_step", &o->pba.max_b_step, "... and every brightness offset b by less than this (grey levels).");
  Add(&e, "pba.max_fit_samples", &o->pba.robust.max_fit_samples,
      "The bundle adjustment's error models are fitted to at most this many residuals (evenly strided).");
  Add(&e, "pba.texture_loss_min_host_variance", &o->pba.texture_loss.min_host_variance,
      "Texture loss (system.texture_loss_min_noise): a point whose pattern varies less than this in its host "
      "(grey levels^2) has no texture to lose ...");
  Add(&e, "pba.texture_loss_max_depth_ratio", &o->pba.texture_loss.max_depth_ratio,
      "... and a target that sees it at more than this ratio of the host's depth, or less than its inverse, is "
      "not judged.");
  // The robust function applies to the bundle adjustment and the tracker alike.
  RobustOptions* pba = &o->pba.robust;
  RobustOptions* tracker = &o->tracker.robust;
  e.push_back({"robust.function",
               [pba, tracker](const YAML::Node& n) {
                 pba->kind = tracker->kind = ParseRobustKind(n.as<std::string>(), "robust.function");
               },
               [pba] { return RobustKindName(pba->kind); },
               "t | huber | huber-mad: the robust function of the bundle adjustment and the tracker."});
  const auto both = [&](std::string key, auto member, std::string description) {
    e.push_back({std::move(key),
                 [=](const YAML::Node& n) {
                   using T = std::decay_t<decltype(pba->*member)>;
                   pba->*member = tracker->*member = n.as<T>();
                 },
                 [=] { return Format(pba->*member); }, std::move(description)});
  };
  both("robust.huber_threshold", &RobustOptions::huber_threshold, "Huber's fixed threshold, grey levels.");
  both("robust.inlier_quantile", &RobustOptions::inlier_quantile,
       "Quantile of the fitted model that bounds inlier pixels.");
  both("robust.gross_residual", &RobustOptions::gross_residual,
       "Residuals beyond this are outliers of any model, grey levels.");
  both("robust.min_nu", &RobustOptions::min_nu, "Lower bound of the t-distribution's fitted degrees of freedom.");
  return e;
}

// `source` names the options in messages (a file, or "options").
void ApplyOptionsNode(const YAML::Node& root, const std::filesystem::path& source, SystemOptions* options) {
  if (root.IsNull()) return;
  if (!root.IsMap()) throw InputError(source.string() + ": expected a mapping of sections");
  std::map<std::string, std::function<void(const YAML::Node&)>> setters;
  for (OptionEntry& entry : Entries(options)) setters[entry.key] = std::move(entry.set);
  for (const auto& section : root) {
    const std::string name = KeyName(section.first, source);
    if (!section.second.IsMap()) throw InputError(source.string() + ": section '" + name + "' must be a mapping");
    for (const auto& kv : section.second) {
      const std::string key = name + "." + KeyName(kv.first, source);
      const auto it = setters.find(key);
      if (it == setters.end()) throw InputError(source.string() + ": unknown key '" + key + "'");
      try {
        it->second(kv.second);
      } catch (const YAML::Exception&) {
        throw InputError(source.string() + ": key '" + key + "' has the wrong type");
      }
    }
  }
  try {
    options->Validate();
  } catch (const InputError& e) {
    throw InputError(source.string() + ": " + e.what());
  }
}

}  // namespace

void ApplyOptionsYaml(const std::filesystem::path& path, SystemOptions* options) {
  ApplyOptionsNode(LoadYamlFile(path), path, options);
}

void ApplyOptionsText(const std::string& text, const std::string& source, SystemOptions* options) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ": not valid YAML (" + e.what() + ")");
  }
  ApplyOptionsNode(root, source, options);
}

std::string OptionsYaml(const SystemOptions& options) {
  SystemOptions copy = options;
  std::ostringstream out;
  out << "# dsm options: every key with its value and what it means (dsm run --config FILE reads this).\n";
  std::string section;
  for (const OptionEntry& entry : Entries(&copy)) {
    const size_t dot = entry.key.find('.');
    if (entry.key.substr(0, dot) != section) {
      section = entry.key.substr(0, dot);
      out << section << ":\n";
    }
    out << "  " << entry.key.substr(dot + 1) << ": " << entry.get() << "  # " << entry.description << "\n";
  }
  return out.str();
}

}  // namespace dsm
