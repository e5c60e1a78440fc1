// SPDX-License-Identifier: MIT
#include "dsm/io/options_io.h"

#include <functional>
#include <map>

#include "dsm/io/yaml_file.h"
#include "dsm/util/check.h"

namespace dsm {

namespace {

using Setter = std::function<void(const YAML::Node&)>;

template <typename T>
Setter Set(T* field) {
  return [field](const YAML::Node& n) { *field = n.as<T>(); };
}

std::map<std::string, Setter> Setters(SystemOptions* o) {
  std::map<std::string, Setter> s;
  s["system.pyramid_levels"] = Set(&o->pyramid_levels);
  s["system.max_initialization_frames"] = Set(&o->max_initialization_frames);
  s["system.keep_pyramid_keyframes"] = Set(&o->keep_pyramid_keyframes);
  s["system.smoothing_sigma"] = Set(&o->smoothing_sigma);
  s["system.smoothing_noise_threshold"] = Set(&o->smoothing_noise_threshold);
  s["system.smoothing_auto_sigma"] = Set(&o->smoothing_auto_sigma);
  s["system.interpolation"] = Set(&o->interpolation);
  s["system.bspline_min_noise"] = Set(&o->bspline_min_noise);
  s["system.texture_loss_min_noise"] = Set(&o->texture_loss_min_noise);
  s["system.young_map_ba_first"] = Set(&o->young_map_ba_first);
  s["system.young_map_ba_last"] = Set(&o->young_map_ba_last);
  s["system.young_map_ba_step"] = Set(&o->young_map_ba_step);
  s["system.loop_ba_min_gap"] = Set(&o->loop_ba_min_gap);
  s["system.loop_ba_after_relocalisation"] = Set(&o->loop_ba_after_relocalisation);
  s["system.seam_ba_count"] = Set(&o->seam_ba_count);
  s["system.seam_ba_step"] = Set(&o->seam_ba_step);
  s["system.seam_ba_before"] = Set(&o->seam_ba_before);
  s["system.rejoin_min_outliers"] = Set(&o->rejoin_min_outliers);
  s["system.loop_ba_max_keyframes"] = Set(&o->loop_ba_max_keyframes);
  s["system.loop_ba_max_iterations"] = Set(&o->loop_ba_max_iterations);
  s["initializer.max_corners"] = Set(&o->initializer.max_corners);
  s["initializer.min_parallax_deg"] = Set(&o->initializer.min_parallax_deg);
  s["initializer.max_homography_ratio"] = Set(&o->initializer.max_homography_ratio);
  s["initializer.planar_start"] = Set(&o->initializer.planar_start);
  s["initializer.min_track_share"] = Set(&o->initializer.min_track_share);
  s["initializer.planar_min_homography_ratio"] = Set(&o->initializer.planar_min_homography_ratio);
  s["initializer.planar_frame_gap"] = Set(&o->initializer.planar_frame_gap);
  s["initializer.planar_normal_tolerance_deg"] = Set(&o->initializer.planar_normal_tolerance_deg);
  s["initializer.min_inliers"] = Set(&o->initializer.min_inliers);
  s["initializer.ransac_threshold_px"] = Set(&o->initializer.ransac_threshold_px);
  s["initializer.track_from_reference"] = Set(&o->initializer.track_from_reference);
  s["initializer.refine_motion"] = Set(&o->initializer.refine_motion);
  s["initializer.refine_loss_px"] = Set(&o->initializer.refine_loss_px);
  s["tracker.levels"] = Set(&o->tracker.levels);
  s["tracker.iterations"] = Set(&o->tracker.iterations);
  s["tracker.min_usage"] = Set(&o->tracker.min_usage);
  s["tracker.convergence_px"] = Set(&o->tracker.convergence_px);
  s["tracker.verified_reference"] = Set(&o->tracker.verified_reference);
  s["tracker.max_alpha_step"] = Set(&o->tracker.max_alpha_step);
  s["tracker.max_alpha_frames"] = Set(&o->tracker.max_alpha_frames);
  s["candidates.target_count"] = Set(&o->candidates.target_count);
  s["candidates.threshold_margin"] = Set(&o->candidates.threshold_margin);
  s["candidates.noise_factor"] = Set(&o->candidates.noise_factor);
  s["candidates.contrast_factor"] = Set(&o->candidates.contrast_factor);
  s["candidates.contrast_min_noise"] = Set(&o->candidates.contrast_min_noise);
  s["candidates.border"] = Set(&o->candidates.border);
  s["epipolar.max_search_fraction"] = Set(&o->epipolar.max_search_fraction);
  s["epipolar.min_search_px"] = Set(&o->epipolar.min_search_px);
  s["epipolar.max_pixel_error"] = Set(&o->epipolar.max_pixel_error);
  s["epipolar.max_energy"] = Set(&o->epipolar.max_energy);
  s["activation.target_points"] = Set(&o->activation.target_points);
  s["activation.max_pixel_interval"] = Set(&o->activation.max_pixel_interval);
  s["activation.min_quality"] = Set(&o->activation.min_quality);
  s["activation.refine_iterations"] = Set(&o->activation.refine_iterations);
  s["activation.min_inlier_ratio"] = Set(&o->activation.min_inlier_ratio);
  s["activation.initial_min_distance_px"] = Set(&o->activation.initial_min_distance_px);
  s["keyframe.weight_parallax"] = Set(&o->keyframe.weight_parallax);
  s["keyframe.weight_visibility"] = Set(&o->keyframe.weight_visibility);
  s["keyframe.weight_brightness"] = Set(&o->keyframe.weight_brightness);
  s["keyframe.residual_growth"] = Set(&o->keyframe.residual_growth);
  s["quality.min_texture_ratio"] = Set(&o->quality.min_texture_ratio);
  s["quality.min_relocalisation_texture_ratio"] = Set(&o->quality.min_relocalisation_texture_ratio);
  s["quality.min_keyframe_texture_step"] = Set(&o->quality.min_keyframe_texture_step);
  s["quality.min_turn_deg"] = Set(&o->quality.min_turn_deg);
  s["quality.max_residual_ratio"] = Set(&o->quality.max_residual_ratio);
  s["quality.max_relocalisation_residual_ratio"] = Set(&o->quality.max_relocalisation_residual_ratio);
  s["quality.min_inlier_ratio"] = Set(&o->quality.min_inlier_ratio);
  s["quality.max_rotation_deg"] = Set(&o->quality.max_rotation_deg);
  s["quality.max_parallax"] = Set(&o->quality.max_parallax);
  s["quality.max_speed_ratio"] = Set(&o->quality.max_speed_ratio);
  s["quality.min_speed"] = Set(&o->quality.min_speed);
  s["quality.history"] = Set(&o->quality.history);
  s["quality.min_history"] = Set(&o->quality.min_history);
  s["relocalisation.candidates"] = Set(&o->relocalisation.candidates);
  s["relocalisation.max_lost_frames"] = Set(&o->relocalisation.max_lost_frames);
  s["relocalisation.max_predicted_frames"] = Set(&o->relocalisation.max_predicted_frames);
  s["relocalisation.young_map_frames"] = Set(&o->relocalisation.young_map_frames);
  s["window.temporal_keyframes"] = Set(&o->window.temporal_keyframes);
  s["window.min_visible_ratio"] = Set(&o->window.min_visible_ratio);
  s["window.max_affine_change"] = Set(&o->window.max_affine_change);
  s["window.covisible_keyframes"] = Set(&o->window.covisible_keyframes);
  s["window.depleted_distance_px"] = Set(&o->window.depleted_distance_px);
  s["window.max_view_angle_deg"] = Set(&o->window.max_view_angle_deg);
  s["window.min_covisible_ratio"] = Set(&o->window.min_covisible_ratio);
  s["window.max_scale_change"] = Set(&o->window.max_scale_change);
  s["window.optimize_covisible_poses"] = Set(&o->window.optimize_covisible_poses);
  s["occlusion.enabled"] = Set(&o->occlusion.enabled);
  s["occlusion.cell_px"] = Set(&o->occlusion.cell_px);
  s["occlusion.depth_ratio"] = Set(&o->occlusion.depth_ratio);
  s["occlusion.min_occluders"] = Set(&o->occlusion.min_occluders);
  s["occlusion.span_px"] = Set(&o->occlusion.span_px);
  s["occlusion.candidate_interval"] = Set(&o->occlusion.candidate_interval);
  s["occlusion.texture_check"] = Set(&o->occlusion.texture_check);
  s["pba.levels"] = Set(&o->pba.levels);
  s["pba.max_iterations"] = Set(&o->pba.max_iterations);
  s["pba.initial_lambda"] = Set(&o->pba.initial_lambda);
  s["pba.min_camera_observations"] = Set(&o->pba.min_camera_observations);
  s["pba.min_link_ratio"] = Set(&o->pba.min_link_ratio);
  s["pba.max_outside_observations"] = Set(&o->pba.max_outside_observations);
  s["pba.max_outside_keyframes"] = Set(&o->pba.max_outside_keyframes);
  s["pba.outside_observations_per_point"] = Set(&o->pba.outside_observations_per_point);
  s["pba.drop_outlier_ratio"] = Set(&o->pba.drop_outlier_ratio);
  s["pba.skip_outlier_ratio"] = Set(&o->pba.skip_outlier_ratio);
  s["pba.max_sigma_ratio"] = Set(&o->pba.max_sigma_ratio);
  s["pba.refit_all_models"] = Set(&o->pba.refit_all_models);
  s["pba.texture_loss_ratio"] = Set(&o->pba.texture_loss.max_variance_ratio);
  s["pba.texture_min_host_variance"] = Set(&o->pba.texture_loss.min_host_variance);
  s["pba.texture_max_depth_ratio"] = Set(&o->pba.texture_loss.max_depth_ratio);
  s["pba.texture_loss_in_energy"] = Set(&o->pba.texture_loss.in_energy);
  // The robust function applies to the bundle adjustment and the tracker alike.
  s["robust.function"] = [o](const YAML::Node& n) {
    const RobustKind kind = ParseRobustKind(n.as<std::string>(), "robust.function");
    o->pba.robust.kind = kind;
    o->tracker.robust.kind = kind;
  };
  s["robust.huber_threshold"] = [o](const YAML::Node& n) {
    o->pba.robust.huber_threshold = o->tracker.robust.huber_threshold = n.as<double>();
  };
  s["robust.inlier_quantile"] = [o](const YAML::Node& n) {
    o->pba.robust.inlier_quantile = o->tracker.robust.inlier_quantile = n.as<double>();
  };
  s["robust.gross_residual"] = [o](const YAML::Node& n) {
    o->pba.robust.gross_residual = o->tracker.robust.gross_residual = n.as<double>();
  };
  s["robust.min_nu"] = [o](const YAML::Node& n) { o->pba.robust.min_nu = o->tracker.robust.min_nu = n.as<double>(); };
  s["robust.outlier_mixture"] = [o](const YAML::Node& n) {
    o->pba.robust.outlier_mixture = o->tracker.robust.outlier_mixture = n.as<bool>();
  };
  return s;
}

}  // namespace

namespace {

// `source` names the options in messages (a file, or "options").
void ApplyOptionsNode(const YAML::Node& root, const std::filesystem::path& source, SystemOptions* options) {
  if (root.IsNull()) return;
  if (!root.IsMap()) throw InputError(source.string() + ": expected a mapping of sections");
  const auto setters = Setters(options);
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

}  // namespace dsm
