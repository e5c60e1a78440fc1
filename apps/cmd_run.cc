// SPDX-License-Identifier: MIT
#include <cstdio>
#include <limits>
#include <optional>

#include "apps/commands.h"
#include "dsm/io/calibration_io.h"
#include "dsm/config/option_registry.h"
#include "dsm/run/interrupt.h"
#include "dsm/run/run.h"
#include "dsm/util/check.h"

namespace dsm::cli {

namespace {

struct RunArgs {
  std::string dataset, out = "dsm_out", mode = "dsm", config, robust, debug;
  double progress_interval = 10.0;
  double latency_target_ms = std::numeric_limits<double>::infinity();
  int port = 8080;
  double view_wait = 0.0;
  bool view = false;
  int start = 0, end = -1, workers = 0;
  std::optional<int> nt, nc, pba_levels;
  std::optional<double> line_delay_us;
  bool print_config = false;
  bool quiet = false, no_map = false, no_report = false, global_ba = false, no_loop_closure = false, truth_ba = false, sequential = false,
       realtime = false, localize = false;
  std::string save_map, load_map, mcap;
  std::string camera, record;
  double duration = 0.0, stall_timeout = 5.0;
  GtArgs gt;
  InputArgs video;
};

// The run's options from the command line (--print-config: the system's options alone).
RunOptions OptionsFrom(const RunArgs& a) {
  RunOptions options;
  options.system.mode = ParseMapMode(a.mode, "--mode");
  if (!a.config.empty()) ApplyOptionsYaml(a.config, &options.system);
  SystemOptions& o = options.system;
  // A flag's value is checked by the option it sets, with the flag named in the message.
  const auto set = [&o](const char* flag, const std::optional<int>& value, int* field) {
    if (!value) return;
    *field = *value;
    try {
      o.Validate();
    } catch (const InputError& e) {
      throw InputError(std::string(flag) + " " + std::to_string(*value) + ": " + e.what());
    }
  };
  set("--nt", a.nt, &o.window.temporal_keyframes);
  set("--nc", a.nc, &o.window.covisible_keyframes);
  set("--pba-levels", a.pba_levels, &o.pba.levels);
  if (a.no_loop_closure) o.loop_closure.enabled = false;
  if (!a.robust.empty()) o.pba.robust.kind = o.tracker.robust.kind = ParseRobustKind(a.robust, "--robust");
  options.system.Validate();
  if (a.print_config) return options;
  if (a.dataset.empty() && a.camera.empty())
    throw InputError("run: DATASET is required (a dataset folder, or a video file with --calib), or --camera");
  if (!a.dataset.empty() && !a.camera.empty()) throw InputError("run: give DATASET or --camera, one of them");
  options.global_ba = a.global_ba;
  options.truth_ba = a.truth_ba;
  options.start = a.start;
  options.end = a.end;
  options.quiet = a.quiet;
  if (!(a.progress_interval >= 0.0)) throw InputError("--progress-interval must be >= 0 seconds");
  options.progress_interval_s = a.progress_interval;
  if (!(a.latency_target_ms >= 0.0)) throw InputError("--latency-target-ms must be >= 0");
  options.realtime_latency_target_ms = a.latency_target_ms;
  options.write_map = !a.no_map;
  options.write_report = !a.no_report;
  options.save_map = a.save_map;
  options.mcap = a.mcap;
  options.load_map = a.load_map;
  options.localize = a.localize;
  if (a.port < 0 || a.port > 65535) throw InputError("--port must be 0..65535");
  options.view_port = a.view ? a.port : -1;
  if (!(a.view_wait >= 0.0) || a.view_wait > 86400.0) throw InputError("--view-wait must be 0..86400 seconds");
  if (a.view_wait > 0.0 && !a.view) throw InputError("--view-wait needs --view");
  options.view_wait_s = a.view_wait;
  options.debug_dir = a.debug;
  options.workers = a.workers;
  if (a.sequential && a.realtime) throw InputError("--sequential and --realtime exclude each other");
  if (!a.camera.empty() && a.sequential) throw InputError("--camera runs in the realtime pace: --sequential is for recordings");
  options.pace = a.sequential ? Pace::kSequential : a.realtime || !a.camera.empty() ? Pace::kRealtime : Pace::kFree;
  // The per-keyframe diagnostics read the map after each keyframe: only sequential allows that.
  if (!options.debug_dir.empty() && !a.realtime) options.pace = Pace::kSequential;
  return options;
}

// The shell's convention for a process ended by a signal: 128 + its number (SIGINT 130, SIGTERM 143).
int ExitCode(const RunSummary& summary) {
  std::printf("%s%s\n", summary.line.c_str(), summary.interrupt_signal ? " (interrupted)" : "");
  return summary.interrupt_signal ? 128 + summary.interrupt_signal : 0;
}

int RunLiveCamera(const RunArgs& a, const RunOptions& options) {
  if (a.video.calib.empty())
    throw InputError("--camera needs the camera's calibration (--calib camera.yaml; dsm calibrate writes one)");
  if (!a.video.ground_truth.empty() || a.video.time_offset_s != 0.0)
    throw InputError("--groundtruth and --time-offset are for video files, not for --camera");
  if (!(a.duration >= 0.0)) throw InputError("--duration must be >= 0 seconds");
  Dataset camera;
  const CameraYaml yaml = ReadCameraYaml(a.video.calib);
  camera.camera = yaml.camera;
  camera.calibration_file = a.video.calib;
  if (a.line_delay_us || yaml.line_delay_us) {
    camera.line_delay_us = a.line_delay_us ? *a.line_delay_us : *yaml.line_delay_us;
    camera.line_delay_source = a.line_delay_us ? LineDelaySource::kOption : LineDelaySource::kCalibration;
  }
  if (!ReadoutFits(camera.line_delay_us, camera.camera.height, 1e6 / yaml.rate_hz))
    throw InputError("--line-delay-us: the readout of " + std::to_string(camera.camera.height) +
                     " rows does not fit the frame interval of " + a.video.calib + " (rate_hz)");
  LiveCamera live({a.camera, a.stall_timeout, a.record, a.duration}, std::move(camera));
  std::printf("camera: %s opened%s\n", a.camera.c_str(), a.record.empty() ? "" : (", recording into " + a.record).c_str());
  std::fflush(stdout);
  CatchInterrupts();
  const RunSummary summary = RunCamera(live, options, a.out);
  std::printf("%s\n", summary.stats["live"]["message"].get<std::string>().c_str());
  return ExitCode(summary);
}

}  // namespace

Command AddRun(CLI::App& app) {
  auto a = std::make_shared<RunArgs>();
  app.add_option("DATASET", a->dataset,
                 "Dataset folder, or a video file (mp4, avi, mkv, ...) with --calib (or --camera for a live camera)");
  app.add_option("--out", a->out, "Output folder (default ./dsm_out)");
  app.add_option("--mode", a->mode,
                 "dsm (persistent map: temporal + covisible window, default) | sw (sliding window of N_t + N_c "
                 "temporal keyframes)");
  app.add_option("--config", a->config, "YAML file with options (dsm run --print-config writes them all)");
  app.add_flag("--print-config", a->print_config,
               "Write every option (after --config and the switches) with its value and meaning as a YAML file "
               "to stdout, and run nothing");
  app.add_option("--start", a->start, "First frame index");
  app.add_option("--end", a->end, "One past the last frame index");
  app.add_flag("--quiet", a->quiet, "Print only the summary (no progress, no lost / relocalised lines)");
  app.add_option("--progress-interval", a->progress_interval,
                 "Seconds between progress lines when stdout is not a terminal (default 10; a terminal shows "
                 "one line updated in place)");
  app.add_flag("--sequential", a->sequential,
               "One thread: every keyframe mapped before the next frame is tracked (deterministic output)");
  app.add_flag("--realtime", a->realtime,
               "Two threads, frames released at their timestamps like a live camera; frames that arrive while "
               "tracking is busy are dropped and counted (default: two threads, frames fed as fast as tracking "
               "takes them)");
  app.add_option("--latency-target-ms", a->latency_target_ms,
                 "--realtime: frames wait for the keyframe being mapped (then tracked as in the sequential run) never "
                 "so long that a frame is dropped (the default) and, with this, while all but 8% of the frames stay "
                 "within this latency (0: no wait)");
  app.add_option("--workers", a->workers,
                 "Threads of the parallel loops (default 0: one per core; 1: loops run on the tracking and "
                 "mapping threads alone)");
  app.add_option("--debug", a->debug, "Write per-keyframe diagnostics (table, images, points) into this folder");
  app.add_flag("--no-map", a->no_map, "Do not write map.ply and keyframes.ply (the map's points and keyframe centres)");
  app.add_flag("--no-report", a->no_report, "Do not write report.html");
  app.add_option("--save-map", a->save_map,
                 "Write every map of the run (keyframes with images, points, observations) to this map file at the "
                 "end (`dsm map info FILE` describes it)");
  app.add_option("--mcap", a->mcap,
                 "Write the run's results to this MCAP file at the end, as ROS 2 messages Foxglove and the ROS 2 tools "
                 "open: each frame's and keyframe's pose, /tf, the keyframe images, the map's points, the trajectory");
  app.add_option("--load-map", a->load_map,
                 "Start in the maps of this map file (dsm run --save-map): relocalise in them where the camera "
                 "starts in a known place, track and extend them in their frame and scale; a new map elsewhere");
  app.add_flag("--localize", a->localize,
               "With --load-map: localise in its maps without changing them; keyframes made where the camera "
               "leaves the mapped area are temporary and retired once it is back (--save-map then writes the "
               "loaded maps unchanged)");
  app.add_flag("--view", a->view,
               "Live viewer: serve the report page on localhost while the run goes on (map, camera and "
               "statistics pushed over a WebSocket); its address is printed");
  app.add_option("--port", a->port, "Port of --view (default 8080; 0: any free port)");
  app.add_option("--view-wait", a->view_wait,
                 "--view: before the first frame, wait up to this many seconds for a browser to connect, so "
                 "that it sees the whole run (default 0: no wait)");
  app.add_option("--line-delay-us", a->line_delay_us,
                 "Rolling shutter: microseconds between two rows' exposures, instead of what the calibration "
                 "says (camera.yaml line_delay_us; none for EuRoC, TUM or a video); 0: a global shutter");
  app.add_flag("--global-ba", a->global_ba, "Bundle-adjust all keyframes and points once after the last frame");
  app.add_flag("--no-loop-closure", a->no_loop_closure,
               "Do not recognise places seen before to close loops (loop_closure.enabled false): the map joins them only "
               "where re-observation reaches");
  app.add_flag("--truth-ba", a->truth_ba,
               "Diagnostic, with ground truth: after the outputs are written, bundle-adjust the whole map again "
               "from the true keyframe poses; how far it ends from them (eval.json keyframes_truth_ba, "
               "keyframes_truth_ba.tum) is the bias of the map's own energy, apart from drift");
  // Ablation switches (paper VII-A); they override the config file.
  app.add_option("--nt", a->nt, "Temporal keyframes N_t (window.temporal_keyframes, 2..20)");
  app.add_option("--nc", a->nc,
                 "Covisible keyframes N_c (window.covisible_keyframes, 0..20; in --mode sw they add to the temporal window)");
  app.add_option("--pba-levels", a->pba_levels, "Pyramid levels of the bundle adjustment (pba.levels, 1..5)");
  app.add_option("--robust", a->robust, "t | huber | huber-mad (robust.function)");
  app.add_option("--camera", a->camera,
                 "A live camera instead of DATASET: a V4L2 device (/dev/video0 or its index 0) or a stream URL (rtsp://, "
                 "http://, tcp://, udp://, ... through FFmpeg), with --calib; realtime pace, frames stamped at capture");
  app.add_option("--record", a->record,
                 "--camera: write every frame captured into this folder as a dataset dsm run replays");
  app.add_option("--duration", a->duration, "--camera: stop after this many seconds (default: at the stream's end)");
  app.add_option("--stall-timeout", a->stall_timeout,
                 "--camera: a stream that sends no frame for this many seconds has ended (default 5)");
  AddGtOptions(app, &a->gt);
  AddInputOptions(app, &a->video);
  return [a] {
    const RunOptions options = OptionsFrom(*a);
    if (a->print_config) {
      std::fputs(OptionsYaml(options.system).c_str(), stdout);
      return 0;
    }
    if (!a->camera.empty()) return RunLiveCamera(*a, options);
    Dataset dataset = OpenInput(a->dataset, a->gt, a->video);
    if (a->line_delay_us) {
      const int rows = dataset.camera.height;
      // The readout fits in the frame interval (taken from the first two frames).
      const double interval_us = dataset.size() >= 2 ? (dataset.frames[1].t_ns - dataset.frames[0].t_ns) * 1e-3 : 1e6;
      if (!ReadoutFits(*a->line_delay_us, rows, interval_us))
        throw InputError("--line-delay-us must be within 0 and the frame interval over the " + std::to_string(rows) +
                         " rows (" + std::to_string(interval_us / rows) + " us)");
      dataset.line_delay_us = *a->line_delay_us;
      dataset.line_delay_source = LineDelaySource::kOption;
    }
    CatchInterrupts();
    return ExitCode(RunDataset(dataset, options, a->out));
  };
}

}  // namespace dsm::cli
