// SPDX-License-Identifier: MIT
// `dsm vocabulary`: trains the vocabulary of visual words that place recognition uses
// (place/vocabulary.h) on ORB features of rendered synthetic frames. The built-in one,
// data/orb_vocabulary.bin, is this command's output with its defaults: the scenes of its --scenes
// rendered with seeds the accuracy tables never use (101-103), so that the scenes they measure on
// have textures the vocabulary was not trained on.
#include <cstdio>
#include <memory>

#include <tbb/parallel_for.h>

#include "apps/commands.h"
#include "dsm/image/pyramid.h"
#include "dsm/place/vocabulary.h"
#include "dsm/synth/renderer.h"
#include "dsm/synth/scenes.h"
#include "dsm/tracking/feature_pose.h"
#include "dsm/util/check.h"

namespace dsm::cli {

Command AddVocabulary(CLI::App& app) {
  struct Args {
    std::string out;
    std::vector<uint32_t> seeds = {101, 102, 103};
    std::vector<std::string> scenes = {"loop", "shake", "forward", "rotation", "exposure",
                                       "orbit", "pan", "block", "twins"};
    int every = 10;
    double noise = 2.0;
    VocabularyOptions tree;
  };
  auto a = std::make_shared<Args>();
  app.add_option("--out", a->out, "The vocabulary file to write")->required();
  app.add_option("--seeds", a->seeds, "Seeds every scene is rendered with (textures)");
  app.add_option("--scenes", a->scenes, "Scenes rendered (the built-in vocabulary's by default)")
      ->check(CLI::IsMember(synth::SceneNames()));
  app.add_option("--every", a->every, "Every how many frames one is taken")->check(CLI::Range(1, 1000));
  app.add_option("--noise", a->noise, "Image noise of the frames, grey levels")->check(CLI::Range(0.0, 50.0));
  app.add_option("--branching", a->tree.branching, "Children per node of the tree");
  app.add_option("--levels", a->tree.levels, "Levels of the tree (words: branching^levels)");
  return [a] {
    struct Frame {
      synth::SynthSequence* sequence;
      size_t index;
    };
    std::vector<std::unique_ptr<synth::SynthSequence>> sequences;
    std::vector<Frame> frames;
    for (const std::string& scene : a->scenes)
      for (uint32_t seed : a->seeds) {
        synth::SynthOptions o;
        o.scene = scene, o.seed = seed, o.noise_sigma = a->noise;
        sequences.push_back(std::make_unique<synth::SynthSequence>(synth::MakeSequence(o)));
        for (size_t i = 0; i < sequences.back()->size(); i += a->every) frames.push_back({sequences.back().get(), i});
      }
    std::printf("rendering %zu frames of %zu scenes\n", frames.size(), a->scenes.size());
    std::fflush(stdout);
    std::vector<cv::Mat> descriptors(frames.size());
    tbb::parallel_for(size_t{0}, frames.size(), [&](size_t f) {
      synth::FormationOptions formation;
      formation.noise_sigma = a->noise;
      formation.noise_seed = static_cast<uint32_t>(f);
      const synth::RenderedFrame r = synth::RenderSequenceFrame(*frames[f].sequence, frames[f].index, formation);
      descriptors[f] = DetectOrbFeatures(ImagePyramid(r.image, 1, false), {}).descriptors;
    });
    size_t total = 0;
    for (const cv::Mat& d : descriptors) total += d.rows;
    std::printf("training on %zu descriptors: %d levels of %d\n", total, a->tree.levels, a->tree.branching);
    std::fflush(stdout);
    const Vocabulary v = Vocabulary::Train(descriptors, a->tree);
    v.Write(a->out);
    std::printf("wrote %s: %d words\n", a->out.c_str(), v.NumWords());
    return 0;
  };
}

}  // namespace dsm::cli
