// SPDX-License-Identifier: MIT
#include <cstdio>

#include "apps/commands.h"
#include "dsm/calibration/board_render.h"
#include "dsm/synth/scenes.h"
#include "dsm/util/check.h"
#include "dsm/synth/sequence_writer.h"

namespace dsm::cli {

namespace {

struct BoardArgs {
  std::string spec;
  int views = 24;
};

}  // namespace

Command AddSynth(CLI::App& app) {
  auto o = std::make_shared<synth::SynthOptions>();
  auto out = std::make_shared<std::string>();
  auto board = std::make_shared<BoardArgs>();
  auto model = std::make_shared<std::string>();
  CLI::Option* scene = app.add_option("--scene", o->scene, synth::SceneNameList(" | ", " | "));
  app.add_option("--board", board->spec,
                 "Instead of a scene: views of a calibration board (checkerboard:COLSxROWS:SQUARE_M or "
                 "charuco:COLSxROWS:SQUARE_M:MARKER_M:DICT, as dsm calibrate reads them) seen by a camera "
                 "of --model (camera.yaml holds its truth; dsm calibrate finds it back)");
  app.add_option("--model", *model,
                 "The camera's lens: pinhole | radtan | equidistant | fov (default: pinhole for --scene, radtan for "
                 "--board); a scene's lens keeps the pinhole's focal length and adds a typical distortion");
  app.add_option("--views", board->views, "--board: how many views (default 24)");
  app.add_option("--out", *out, "Output folder (generic folder format)")->required();
  app.add_option("--frames", o->frames, "Number of frames (default: the scene's own length)");
  app.add_option("--seed", o->seed, "Seed of textures and hand-held jitter");
  app.add_option("--width", o->width, "Image width in pixels");
  app.add_option("--height", o->height, "Image height in pixels");
  app.add_option("--rate", o->rate_hz, "Frame rate, Hz");
  app.add_option("--noise", o->noise_sigma, "Gaussian image noise, grey levels (default 1)");
  app.add_option("--vignette", o->vignette, "Vignetting strength in the corners, 0..0.8 (writes vignette.png)");
  app.add_option("--blur", o->blur_sigma, "Gaussian optical blur sigma, pixels");
  app.add_option("--rolling-shutter", o->line_delay_us,
                 "Rolling shutter: microseconds between two rows' exposures, e.g. 30 as phones have (default 0: a "
                 "global shutter); written to camera.yaml as line_delay_us");
  app.add_flag("--depth", o->depth, "Also write per-frame depth maps (depth/*.tiff, metres)");
  app.add_flag("--turned-textures", o->turned_textures,
               "Textures that do not repeat along the surfaces (each reads its noise tile along turned axes; "
               "by default they repeat every two of their coarsest wavelengths, e.g. every 2 m down the corridor)");
  app.add_flag("--plain-pillars", o->plain_pillars,
               "Floor-to-ceiling pillars (orbit's, the corridor's) nearly without texture, like painted plaster: "
               "points only along their silhouettes");
  app.add_option("--defects", o->defects,
                 "Bad frames to inject: KIND:FIRST[-LAST],... with KIND black, saturated, noise, cover (a hand "
                 "over the lens), corrupt, truncated or empty (damaged files), e.g. black:200-214,corrupt:350");
  return [o, out, board, model, scene] {
    if (board->spec.empty() == (scene->count() == 0)) throw InputError("synth: give --scene or --board, one of them");
    if (!board->spec.empty()) {
      const BoardSpec spec = BoardSpec::Parse(board->spec, "--board");
      const CameraCalibration camera = ExampleCamera(ParseCameraModel(model->empty() ? "radtan" : *model, "--model"));
      if (board->views < 1 || board->views > 1000) throw InputError("--views must be 1..1000");
      WriteBoardSequence(*out, camera, spec, board->views, o->seed);
      std::printf("done: %d views of %s by a %s camera in %s\n", board->views, spec.ToString().c_str(),
                  CameraModelName(camera.model).c_str(), out->c_str());
      return 0;
    }
    if (!model->empty()) o->model = ParseCameraModel(*model, "--model");
    const synth::SynthSequence seq = synth::MakeSequence(*o);
    std::printf("rendering scene '%s': %zu frames %dx%d (%s) into %s\n", o->scene.c_str(), seq.size(), o->width,
                o->height, CameraModelName(o->model).c_str(), out->c_str());
    const synth::WriteSummary s = synth::WriteSequence(seq, *o, *out, [](size_t done, size_t total) {
      if (done % 96 == 0 || done == total) std::printf("  %zu/%zu frames\n", done, total), std::fflush(stdout);
    });
    std::printf("done: %zu frames, camera path %.2f m, ray casting %.1f ms per frame on one core\n", s.frames, s.path_length_m,
                s.render_ms_mean);
    return 0;
  };
}

}  // namespace dsm::cli
