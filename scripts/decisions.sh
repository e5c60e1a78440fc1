#!/usr/bin/env bash
# The decisions that change a map, judged against exact ground truth: every relocalisation, new
# map, merge and loop closure of runs over rendered scenes with a cut (frames left out: the camera
# reappears elsewhere) or a hand over the lens, at two positions per scene, in the sequential and
# the default (free) pace. Prints a markdown table, a row per scene and pace, then one row per
# relocalisation with its evidence (stats.json `relocalised`) and its judgement, and writes both to
# docs/results.md (section `decisions`, scripts/results.sh).
#
# Usage: ./scripts/decisions.sh [--jobs N] [--scenes "loop orbit"] [--seeds "1 2"] [--paces "sequential free"]
#                               [--work DIR] [--reuse]
#        ./scripts/decisions.sh --print-header   the table's header alone (no build, no run)
#   scenes: loop orbit exposure twins (600 frames: the camera comes back to what it mapped),
#           forward (the corridor, whose textures repeat every 2 m) and forward-turned (its textures
#           turned), rotation (300 frames)
#   reuse:  a run whose stats.json is in the work folder from before is not run again (to resume an
#           interrupted battery, or to judge its runs again; same binary only)
#   DSM_BIN=path   this dsm binary (no set-up or build)
# How each decision is judged:
#   relocalisation  (stats.json `relocalised`: in the map the camera was lost from, or a suspended
#                   map it came back to) the relocalised frame lies within 5 cm of the truth (the
#                   map aligned to the ground truth by Sim(3), the error in the truth's metres):
#                   right, else wrong; `frames` is the median of the frames lost after the defect
#                   that caused the loss had ended
#   new map, merge  right when the map it makes (merged whole) has a keyframe ATE <= 5 mm
#   loop            a run that closes loops is run again with --no-loop-closure: its loops are right
#                   when the keyframe ATE is at most 1.05x that run's
# Renders are kept in WORK (default /tmp/dsm_decisions); runs are redone.
set -euo pipefail
cd "$(dirname "$0")/.."
RESULTS_COLUMNS=("scene" "pace" "runs" "losses" "relocalised right / wrong" "frames lost after the defect (median)" "new maps" "merges right / wrong" "loops right / wrong" "maps with ATE > 5 mm")
source scripts/results.sh
RESULTS_ARGS=$(results_args "$@")

JOBS=1
SCENES="loop orbit exposure twins forward forward-turned rotation"
SEEDS="1 2 3 4 5"
PACES="sequential free"
WORK=/tmp/dsm_decisions
REUSE=0
while (($#)); do
  case "$1" in
    --jobs) JOBS="$2"; shift 2 ;;
    --scenes) SCENES="$2"; shift 2 ;;
    --seeds) SEEDS="$2"; shift 2 ;;
    --paces) PACES="$2"; shift 2 ;;
    --work) WORK="$2"; shift 2 ;;
    --reuse) REUSE=1; shift ;;
    *) echo "decisions.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
source scripts/dsm_binary.sh
mkdir -p "$WORK"

# The two defect positions of a scene: a cut and a hand, early and late in the recording.
defects_of() {  # defects_of SCENE POSITION
  case "$1:$2" in
    forward*:1 | rotation:1) echo "cut:60-129" ;;
    forward*:2 | rotation:2) echo "cover:100-130,cut:180-219" ;;
    *:1) echo "cut:150-199,cover:400-430" ;;
    *:2) echo "cover:100-130,cut:300-369" ;;
  esac
}

render() {  # render SCENE SEED POSITION DIR
  local scene=$1 extra=()
  if [ "$scene" = forward-turned ]; then scene=forward extra=(--turned-textures); fi
  if [ ! -f "$4/groundtruth.tum" ]; then
    "$DSM" synth --scene "$scene" --seed "$2" --defects "$(defects_of "$1" "$3")" ${extra[@]+"${extra[@]}"} \
      --out "$4" >/dev/null
  fi
}

# The judgement of one run folder, as JSON (losses, relocalisations right and wrong with the frames
# each took and its evidence, new maps, merges right and wrong, maps over 5 mm, loops, ATE), from
# stats.json, the maps' trajectories and the rendering's truth.
JUDGE='
import functools, json, math, os, sys
run, seq, defects = sys.argv[1], sys.argv[2], sys.argv[3]
# The defects in the frame indices of the run: a cut leaves its frames out of the recording, so the
# frames after it move back by its length; the last index of each defect (a cut: the frame before
# the one it jumps to).
spans = [(k, *map(int, (r.split("-") + [r])[:2])) for k, r in (d.split(":") for d in defects.split(","))]
def shifted(i): return i - sum(b - a + 1 for k, a, b in spans if k == "cut" and b < i)
ends = sorted(shifted(a) - 1 if k == "cut" else shifted(b) for k, a, b in spans)
stats = json.load(open(os.path.join(run, "stats.json")))
def tum(path):
    rows = {}
    if os.path.exists(path):
        for line in open(path):
            f = line.split()
            if len(f) >= 4 and not line.startswith("#"):
                rows[round(float(f[0]) * 1e3)] = tuple(map(float, f[1:4]))
    return rows
stamps = [round(int(l.split()[0]) / 1e6) for l in open(os.path.join(seq, "times.txt"))
          if l.strip() and not l.startswith("#")]
truth = tum(os.path.join(seq, "groundtruth.tum"))
maps = [m for m in stats["maps"] if m.get("dir") is not None]
def map_of(frame):
    for m in maps:
        if any(a <= frame <= b for a, b in (m.get("spans") or [])): return m
    return None
# The frames of a map, its truth in the frame of the map, and the scale of the truth over the map
# (read once per map).
@functools.lru_cache(maxsize=None)
def trajectories(map_dir):
    est, gt = tum(os.path.join(run, map_dir, "frames.tum")), tum(os.path.join(run, map_dir, "groundtruth_in_map.tum"))
    keys = sorted(k for k in est if k in gt and k in truth)
    path_map = sum(math.dist(gt[a], gt[b]) for a, b in zip(keys, keys[1:]))
    path_world = sum(math.dist(truth[a], truth[b]) for a, b in zip(keys, keys[1:]))
    return est, gt, len(keys), (path_world / path_map if path_map > 0 else 1.0)
def error_m(m, frame):
    est, gt, n, scale = trajectories(m["dir"])
    t = stamps[frame]
    if t not in est or t not in gt or n < 2: return None
    return math.dist(est[t], gt[t]) * scale
right = wrong = 0
frames = []
relocs = []
# Every relocalisation, in the map the loss was in or in a suspended map the camera came back to.
for r in stats.get("relocalised", []):
    frame = r["frame"]
    m = map_of(frame)
    e = error_m(m, frame) if m is not None and frame < len(stamps) else None
    if e is None: continue
    # Frames lost after the defect that caused the loss had ended.
    end = max([d for d in ends if d < frame] or [frame - 1])
    frames.append(frame - 1 - end)
    if e <= 0.05: right += 1
    else: wrong += 1
    relocs.append(dict(r, right=e <= 0.05, error_m=e))
merged = stats.get("maps_merged", [])
bad = sum(1 for m in maps if (m.get("keyframe_ate_m") or 0) > 0.005)
merges_bad = sum(1 for g in merged for m in maps if m["dir"] == "." and (m.get("keyframe_ate_m") or 0) > 0.005)
print(json.dumps({"losses": len(stats["lost_episodes"]), "right": right, "wrong": wrong, "frames": frames,
                  "new_maps": len(stats["maps"]) - 1, "merges_right": len(merged) - merges_bad,
                  "merges_wrong": merges_bad, "bad_maps": bad, "loops": len(stats.get("loops_closed", [])),
                  "relocs": relocs,
                  "ate": (json.load(open(os.path.join(run, "eval.json")))["keyframes"]["ape"]["rmse"]
                          if os.path.exists(os.path.join(run, "eval.json")) else None)}))
'

# One run in PACE (sequential or free, the default), and the same without loop closure where it
# closed loops.
run_one() {  # run_one SEQUENCE OUT PACE
  local seq=$1 out=$2 flag=""
  if [ "$3" = sequential ]; then flag="--sequential"; fi
  if [ "$REUSE" = 1 ] && [ -f "$out/stats.json" ]; then return; fi
  rm -rf "$out" "$out-off"
  "$DSM" run "$seq" $flag --quiet --out "$out" >"$out.log" 2>&1 || true
  if [ -f "$out/stats.json" ] && [ "$(jq '.loops_closed | length' "$out/stats.json")" -gt 0 ]; then
    "$DSM" run "$seq" $flag --no-loop-closure --quiet --out "$out-off" >"$out-off.log" 2>&1 || true
  fi
}
export -f run_one
export DSM REUSE

jobs_list=()
for scene in $SCENES; do
  for seed in $SEEDS; do
    for pos in 1 2; do
      seq="$WORK/seq_${scene}_${seed}_$pos"
      render "$scene" "$seed" "$pos" "$seq"
      for pace in $PACES; do
        jobs_list+=("$seq $WORK/run_${scene}_${seed}_${pos}_$pace $pace")
      done
    done
  done
done
printf '%s\n' "${jobs_list[@]}" | xargs -P "$JOBS" -L 1 bash -c 'run_one "$@"' _

table() {
  results_header
  evidence=()
  for scene in $SCENES; do
    for pace in $PACES; do
      judged=()
      for seed in $SEEDS; do
        for pos in 1 2; do
          out="$WORK/run_${scene}_${seed}_${pos}_$pace"
          [ -f "$out/stats.json" ] || continue  # A run that failed: its log says why.
          j=$(python3 -c "$JUDGE" "$out" "$WORK/seq_${scene}_${seed}_$pos" "$(defects_of "$scene" "$pos")")
          if [ -f "$out-off/eval.json" ]; then
            off=$(jq '.keyframes.ape.rmse' "$out-off/eval.json")
            j=$(jq -c --argjson off "$off" '. + {loops_ok: (if .ate != null and .ate <= 1.05 * $off then .loops else 0 end)}' <<<"$j")
          fi
          judged+=("$j")
          evidence+=("$(jq -c --arg run "$scene $seed $pace" --arg defects "$(defects_of "$scene" "$pos")" \
            '{run: $run, defects: $defects, relocs: .relocs}' <<<"$j")")
        done
      done
      printf '%s\n' "${judged[@]}" | jq -rs --arg scene "$scene" --arg pace "$pace" '
        def median: sort | if length == 0 then "-" else .[length / 2 | floor] end;
        "| \($scene) | \($pace) | \(length) | \(map(.losses // 0) | add) | " +
        "\(map(.right // 0) | add) / \(map(.wrong // 0) | add) | \([.[].frames // [] | .[]] | median) | " +
        "\(map(.new_maps // 0) | add) | \(map(.merges_right // 0) | add) / \(map(.merges_wrong // 0) | add) | " +
        "\(map(.loops_ok // 0) | add) / \(map((.loops // 0) - (.loops_ok // 0)) | add) | " +
        "\(map(.bad_maps // 0) | add) |"'
    done
  done
  # Each relocalisation with its evidence (stats.json `relocalised`) and how it was judged.
  echo
  echo "| run (scene seed pace) | defects | frame | frames lost | accepted by | inliers / level | residual / level | margin | judged |"
  echo "|---|---|---|---|---|---|---|---|---|"
  printf '%s\n' "${evidence[@]}" | jq -r '. as $r | .relocs[] |
    "| \($r.run) | \($r.defects) | \(.frame) | \(.frames_lost) | \(if .predicted then "prediction" else "sightings" end) | " +
    "\(.inlier_ratio * 100 | round / 100) / \(.inlier_level * 100 | round / 100) | \(.residual_ratio * 100 | round / 100) | " +
    "\(.margin * 100 | round / 100) | \(if .right then "right" else "wrong, \(.error_m * 100 | round / 100) m off" end) |"'
}
table | results_tee decisions
