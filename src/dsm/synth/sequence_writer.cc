// SPDX-License-Identifier: MIT
#include "dsm/synth/sequence_writer.h"

#include <algorithm>
#include <chrono>

#include <tbb/parallel_for.h>

#include "dsm/io/folder_dataset.h"
#include "dsm/io/image_io.h"
#include "dsm/io/trajectory_io.h"
#include "dsm/image/defects.h"
#include "dsm/synth/renderer.h"
#include "dsm/util/check.h"

namespace dsm::synth {

namespace fs = std::filesystem;

WriteSummary WriteSequence(const SynthSequence& seq, const SynthOptions& options, const fs::path& out,
                           const std::function<void(size_t, size_t)>& progress) {
  std::error_code ec;
  fs::create_directories(out / "images", ec);
  if (ec) throw InputError(out.string() + ": cannot create the output folder (" + ec.message() + ")");
  if (options.depth) fs::create_directories(out / "depth", ec);

  CameraYaml cam;
  cam.camera = seq.Calibration();
  cam.rate_hz = options.rate_hz;
  cam.line_delay_us = options.line_delay_us;
  WriteCameraYaml(out / "camera.yaml", cam);

  Image<float> vignette;
  if (options.vignette > 0.0) {
    vignette = MakeVignette(seq.camera.width, seq.camera.height, options.vignette);
    Image<uint16_t> v16(vignette.width(), vignette.height());
    for (size_t i = 0; i < v16.size(); ++i) v16.data()[i] = static_cast<uint16_t>(std::lround(vignette.data()[i] * 65535.0));
    WriteGray16(out / "vignette.png", v16);
  } else {
    fs::remove(out / "vignette.png", ec);
  }

  const std::vector<Defect> defects = ParseDefects(options.defects);
  std::vector<size_t> kept;  // Rendered frames written, in order (defects.h: cut).
  for (size_t i = 0; i < seq.size(); ++i)
    if (!IsCut(defects, static_cast<int>(i))) kept.push_back(i);
  if (kept.size() < 2 && seq.size() >= 2) throw InputError("--defects: the cuts leave fewer than two frames");
  WriteSummary summary;
  std::vector<FrameRecord> frames(kept.size());
  std::vector<double> render_ms(kept.size(), 0.0);
  // Frames are rendered on one core each, several at a time; every frame's noise has its own
  // seed, so the output does not depend on the schedule.
  constexpr size_t kChunk = 16;
  for (size_t begin = 0; begin < kept.size(); begin += kChunk) {
    const size_t end = std::min(kept.size(), begin + kChunk);
    tbb::parallel_for(begin, end, [&](size_t j) {
      const size_t i = kept[j];
      Image<float> albedo, depth;
      const auto t0 = std::chrono::steady_clock::now();
      RenderSequenceAlbedo(seq, i, &albedo, options.depth ? &depth : nullptr, /*parallel=*/false);
      render_ms[j] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      FormationOptions formation;
      formation.noise_sigma = options.noise_sigma;
      formation.blur_sigma = options.blur_sigma;
      formation.vignette = vignette.empty() ? nullptr : &vignette;
      formation.noise_seed = options.seed * 7919u + static_cast<uint32_t>(i);
      const std::string name = FolderImageName(j);
      Image<uint8_t> image = FormImage(albedo, seq.photometry[i], formation);
      ApplyImageDefects(defects, static_cast<int>(i), options.seed, &image);
      WriteGray8(out / "images" / name, image);
      ApplyFileDefects(defects, static_cast<int>(i), out / "images" / name);
      if (options.depth) WriteFloatTiff(out / "depth" / (name.substr(0, name.size() - 4) + ".tiff"), depth);
      frames[j] = {seq.t_ns[i], name, seq.photometry[i].exposure_ms};
    });
    if (progress) progress(end, kept.size());
  }
  Trajectory gt;
  for (size_t i : kept) gt.Add(seq.t_ns[i], seq.world_from_cam[i]);
  double render_ms_total = 0.0;
  for (double ms : render_ms) render_ms_total += ms;
  WriteFolderTimes(out, frames);
  WriteTumTrajectory(out / "groundtruth.tum", gt);
  summary.frames = kept.size();
  summary.render_ms_mean = kept.empty() ? 0.0 : render_ms_total / kept.size();
  summary.path_length_m = gt.PathLength();
  return summary;
}

}  // namespace dsm::synth
