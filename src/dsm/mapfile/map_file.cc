// SPDX-License-Identifier: MIT
#include "dsm/mapfile/map_file.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "dsm/mapfile/zip_archive.h"
#include "dsm/util/check.h"
#include "dsm/util/version.h"

namespace dsm {
namespace {

static_assert(std::endian::native == std::endian::little, "map files hold little-endian arrays");

using nlohmann::json;

constexpr char kFormat[] = "dsm-map";
constexpr char kManifest[] = "manifest.json";
constexpr int kPatchFloats = 2 + 2 * kPatternSize;
// Bounds that keep a damaged manifest from asking for absurd allocations (far above any map).
constexpr int64_t kMaxKeyframes = 1 << 20, kMaxPoints = int64_t{1} << 28, kMaxObservations = int64_t{1} << 30;
constexpr int kMaxPyramidLevels = 12;
constexpr uint8_t kRemoved = 1, kPatchOk = 2, kPatchBSpline = 4;

template <typename T>
constexpr const char* TypeName() {
  if constexpr (std::is_same_v<T, uint8_t>) return "u8";
  if constexpr (std::is_same_v<T, uint16_t>) return "u16";
  if constexpr (std::is_same_v<T, int32_t>) return "i32";
  if constexpr (std::is_same_v<T, int64_t>) return "i64";
  if constexpr (std::is_same_v<T, float>) return "f32";
  if constexpr (std::is_same_v<T, double>) return "f64";
}

uint32_t Crc32(const void* data, size_t bytes) {
  uLong crc = crc32(0L, Z_NULL, 0);
  const auto* p = static_cast<const Bytef*>(data);
  while (bytes > 0) {  // zlib takes the length as uInt.
    const uInt n = static_cast<uInt>(std::min<size_t>(bytes, 1u << 30));
    crc = crc32(crc, p, n);
    p += n;
    bytes -= n;
  }
  return static_cast<uint32_t>(crc);
}

std::string MapDir(size_t i) { return "maps/" + std::to_string(i) + "/"; }

std::string InterpolationName(Interpolation interpolation) {
  return interpolation == Interpolation::kBSpline ? "bspline" : "bilinear";
}

// ---- Writing -------------------------------------------------------------------------------

class ArrayWriter {
 public:
  ArrayWriter(ZipWriter* zip, json* arrays) : zip_(zip), arrays_(arrays) {}

  template <typename T>
  void Add(const std::string& name, const std::vector<T>& values, std::vector<int64_t> shape) {
    int64_t count = 1;
    for (int64_t d : shape) count *= d;
    DSM_CHECK(count == static_cast<int64_t>(values.size()), "array size and shape disagree");
    std::string bytes(values.size() * sizeof(T), '\0');
    if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
    (*arrays_)[name] = {{"type", TypeName<T>()}, {"shape", shape}, {"crc32", Crc32(bytes.data(), bytes.size())}};
    zip_->Add(name, std::move(bytes));
  }

 private:
  ZipWriter* zip_;
  json* arrays_;
};

void Append(std::vector<float>* out, const Eigen::Vector2f& v) {
  out->push_back(v.x());
  out->push_back(v.y());
}

// Writes map i's arrays; returns its manifest entry.
json WriteMap(const StoredMap& stored, size_t i, const PinholeCamera& camera, ArrayWriter* arrays) {
  const Map& map = stored.map;
  const int64_t K = map.NumKeyframes(), P = map.NumPoints();
  std::vector<int64_t> time;
  std::vector<double> pose, brightness, error_model, signature;
  std::vector<int32_t> levels, thumbnail_size, covisibility_offsets{0}, covisibility;
  std::vector<uint16_t> images;
  std::vector<float> thumbnails;
  images.reserve(static_cast<size_t>(K) * camera.width * camera.height);
  for (int k = 0; k < K; ++k) {
    const Keyframe& kf = map.keyframe(k);
    time.insert(time.end(), {kf.frame_index, kf.t_ns});
    const Eigen::Quaterniond& q = kf.cam_from_world.So3().Quaternion();
    const Eigen::Vector3d& t = kf.cam_from_world.Translation();
    pose.insert(pose.end(), {q.x(), q.y(), q.z(), q.w(), t.x(), t.y(), t.z()});
    brightness.insert(brightness.end(), {kf.affine.a, kf.affine.b, kf.exposure});
    const ErrorModel& m = kf.error_model;
    error_model.insert(error_model.end(), {static_cast<double>(m.kind), m.nu, m.sigma, m.huber_k, m.inlier_threshold,
                                           m.fitted ? 1.0 : 0.0});
    levels.insert(levels.end(), {kf.pyramid_levels, kf.most_pba_links});
    const Image<uint16_t> image = kf.Level0();
    DSM_CHECK(image.width() == camera.width && image.height() == camera.height, "keyframe image of another size");
    images.insert(images.end(), image.data(), image.data() + image.size());
    const FrameSignature& s = kf.signature;
    signature.insert(signature.end(), {s.texture, s.mean, s.deviation});
    const bool thumb = !s.thumbnail.empty();
    thumbnail_size.insert(thumbnail_size.end(), {thumb ? s.width : 0, thumb ? s.height : 0});
    thumbnails.insert(thumbnails.end(), s.thumbnail.begin(), s.thumbnail.end());
    if (static_cast<size_t>(k) < stored.covisibility.size()) {
      const std::vector<int>& c = stored.covisibility[k];
      covisibility.insert(covisibility.end(), c.begin(), c.end());
    }
    covisibility_offsets.push_back(static_cast<int32_t>(covisibility.size()));
  }
  std::vector<int32_t> host, created, observation_offsets{0}, target;
  std::vector<float> pixel, idepth, patch;
  std::vector<uint8_t> flags, outlier;
  for (int id = 0; id < P; ++id) {
    const Point& p = map.point(id);
    host.push_back(p.host);
    Append(&pixel, p.pixel);
    idepth.push_back(p.idepth);
    created.push_back(p.created_at_keyframe);
    flags.push_back((p.removed ? kRemoved : 0) | (p.patch_ok ? kPatchOk : 0) |
                    (p.patch.interpolation == Interpolation::kBSpline ? kPatchBSpline : 0));
    Append(&patch, p.patch.center);
    patch.insert(patch.end(), p.patch.value.begin(), p.patch.value.end());
    patch.insert(patch.end(), p.patch.weight_g.begin(), p.patch.weight_g.end());
    for (const Observation& o : p.observations) {
      target.push_back(o.target);
      outlier.push_back(o.outlier ? 1 : 0);
    }
    observation_offsets.push_back(static_cast<int32_t>(target.size()));
  }
  const std::string dir = MapDir(i);
  const auto T = static_cast<int64_t>(thumbnails.size()), C = static_cast<int64_t>(covisibility.size()),
             O = static_cast<int64_t>(target.size());
  arrays->Add(dir + "keyframe_time", time, {K, 2});
  arrays->Add(dir + "keyframe_pose", pose, {K, 7});
  arrays->Add(dir + "keyframe_brightness", brightness, {K, 3});
  arrays->Add(dir + "keyframe_error_model", error_model, {K, 6});
  arrays->Add(dir + "keyframe_levels", levels, {K, 2});
  arrays->Add(dir + "keyframe_image", images, {K, camera.height, camera.width});
  arrays->Add(dir + "keyframe_signature", signature, {K, 3});
  arrays->Add(dir + "keyframe_thumbnail_size", thumbnail_size, {K, 2});
  arrays->Add(dir + "keyframe_thumbnail", thumbnails, {T});
  arrays->Add(dir + "keyframe_covisibility_offsets", covisibility_offsets, {K + 1});
  arrays->Add(dir + "keyframe_covisibility", covisibility, {C});
  arrays->Add(dir + "point_host", host, {P});
  arrays->Add(dir + "point_pixel", pixel, {P, 2});
  arrays->Add(dir + "point_idepth", idepth, {P});
  arrays->Add(dir + "point_created", created, {P});
  arrays->Add(dir + "point_flags", flags, {P});
  arrays->Add(dir + "point_patch", patch, {P, kPatchFloats});
  arrays->Add(dir + "observation_offsets", observation_offsets, {P + 1});
  arrays->Add(dir + "observation_target", target, {O});
  arrays->Add(dir + "observation_outlier", outlier, {O});
  return {{"keyframes", K},         {"points", P},
          {"observations", O},      {"thumbnail_values", T},
          {"covisibility_links", C}, {"interpolation", InterpolationName(map.interpolation())},
          {"window", stored.window}, {"covisible", stored.covisible},
          {"image_noise_sigma", stored.image_noise_sigma},
          {"tracking_levels", {{"residual", stored.residual_level}, {"texture", stored.texture_level}}}};
}

// ---- Reading -------------------------------------------------------------------------------

// Reads the manifest's values, naming the file and the key in every error.
class Manifest {
 public:
  Manifest(std::string file, json root) : file_(std::move(file)), root_(std::move(root)) {}

  [[noreturn]] void Fail(const std::string& what) const { throw InputError(file_ + ": " + what); }
  const json& At(const json& object, const std::string& key, const std::string& where) const {
    if (!object.is_object() || !object.contains(key)) Fail(where + key + " is missing from the manifest");
    return object.at(key);
  }
  int64_t Int(const json& object, const std::string& key, const std::string& where, int64_t min, int64_t max) const {
    const json& v = At(object, key, where);
    if (!v.is_number_integer() || v.get<int64_t>() < min || v.get<int64_t>() > max) {
      Fail(where + key + " must be an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    }
    return v.get<int64_t>();
  }
  double Number(const json& object, const std::string& key, const std::string& where) const {
    const json& v = At(object, key, where);
    if (!v.is_number() || !std::isfinite(v.get<double>())) Fail(where + key + " must be a finite number");
    return v.get<double>();
  }
  std::string String(const json& object, const std::string& key, const std::string& where) const {
    const json& v = At(object, key, where);
    if (!v.is_string()) Fail(where + key + " must be a string");
    return v.get<std::string>();
  }
  std::vector<int> Ids(const json& object, const std::string& key, const std::string& where, int64_t count) const {
    const json& v = At(object, key, where);
    if (!v.is_array()) Fail(where + key + " must be a list of keyframe ids");
    std::vector<int> ids;
    for (const json& e : v) {
      if (!e.is_number_integer() || e.get<int64_t>() < 0 || e.get<int64_t>() >= count) {
        Fail(where + key + " holds an id outside the map's " + std::to_string(count) + " keyframes");
      }
      ids.push_back(e.get<int>());
    }
    return ids;
  }
  const json& root() const { return root_; }
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  json root_;
};

class ArrayReader {
 public:
  ArrayReader(const ZipReader* zip, const Manifest* manifest) : zip_(zip), manifest_(manifest) {}

  template <typename T>
  std::vector<T> Get(const std::string& name, const std::vector<int64_t>& shape) const {
    const json& arrays = manifest_->At(manifest_->root(), "arrays", "");
    const json& entry = manifest_->At(arrays, name, "arrays.");
    const std::string where = "array " + name;
    if (manifest_->String(entry, "type", "arrays." + name + ".") != TypeName<T>()) {
      manifest_->Fail(where + " is not of type " + TypeName<T>());
    }
    const json& s = manifest_->At(entry, "shape", "arrays." + name + ".");
    if (!s.is_array() || s.size() != shape.size()) manifest_->Fail(where + " has the wrong number of dimensions");
    int64_t count = 1;
    for (size_t d = 0; d < shape.size(); ++d) {
      if (!s[d].is_number_integer() || s[d].get<int64_t>() != shape[d]) {
        manifest_->Fail(where + " has the wrong shape (dimension " + std::to_string(d) + " should be " +
                        std::to_string(shape[d]) + ")");
      }
      count *= shape[d];
    }
    const auto crc = manifest_->Int(entry, "crc32", "arrays." + name + ".", 0, std::numeric_limits<uint32_t>::max());
    const uint64_t bytes = static_cast<uint64_t>(count) * sizeof(T);
    if (zip_->Size(name) != bytes) manifest_->Fail(where + " holds " + std::to_string(zip_->Size(name)) +
                                                   " bytes, not " + std::to_string(bytes));
    const std::string data = zip_->Read(name);
    if (Crc32(data.data(), data.size()) != static_cast<uint32_t>(crc)) manifest_->Fail(where + " is damaged (CRC)");
    std::vector<T> out(count);
    if (bytes > 0) std::memcpy(out.data(), data.data(), bytes);
    return out;
  }

 private:
  const ZipReader* zip_;
  const Manifest* manifest_;
};

PinholeCamera ReadCamera(const Manifest& m) {
  const json& c = m.At(m.root(), "camera", "");
  PinholeCamera camera;
  camera.width = static_cast<int>(m.Int(c, "width", "camera.", 1, 1 << 15));
  camera.height = static_cast<int>(m.Int(c, "height", "camera.", 1, 1 << 15));
  camera.fx = m.Number(c, "fx", "camera.");
  camera.fy = m.Number(c, "fy", "camera.");
  camera.cx = m.Number(c, "cx", "camera.");
  camera.cy = m.Number(c, "cy", "camera.");
  if (!(camera.fx > 0 && camera.fy > 0)) m.Fail("camera.fx and camera.fy must be positive");
  return camera;
}

bool Finite(const float* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

// Checks a CSR offset list: starts at 0, never decreases, ends at `total`.
void CheckOffsets(const Manifest& m, const std::vector<int32_t>& offsets, int64_t total, const std::string& name) {
  if (offsets.front() != 0 || offsets.back() != total) m.Fail(name + " does not span its list");
  for (size_t i = 1; i < offsets.size(); ++i)
    if (offsets[i] < offsets[i - 1]) m.Fail(name + " decreases at " + std::to_string(i));
}

StoredMap ReadMap(const Manifest& m, const ArrayReader& arrays, const json& entry, size_t i, const PinholeCamera& camera) {
  const std::string where = "maps[" + std::to_string(i) + "].";
  const int64_t K = m.Int(entry, "keyframes", where, 0, kMaxKeyframes);
  const int64_t P = m.Int(entry, "points", where, 0, kMaxPoints);
  const int64_t O = m.Int(entry, "observations", where, 0, kMaxObservations);
  const int64_t T = m.Int(entry, "thumbnail_values", where, 0, K * (1 << 16));
  const int64_t C = m.Int(entry, "covisibility_links", where, 0, K * K);
  const std::string interpolation = m.String(entry, "interpolation", where);
  if (interpolation != "bilinear" && interpolation != "bspline") m.Fail(where + "interpolation must be bilinear or bspline");
  StoredMap out;
  out.window = m.Ids(entry, "window", where, K);
  out.covisible = m.Ids(entry, "covisible", where, K);
  out.map.set_interpolation(interpolation == "bspline" ? Interpolation::kBSpline : Interpolation::kBilinear);
  out.image_noise_sigma = m.Number(entry, "image_noise_sigma", where);
  const json& tracking_levels = m.At(entry, "tracking_levels", where);
  out.residual_level = m.Number(tracking_levels, "residual", where + "tracking_levels.");
  out.texture_level = m.Number(tracking_levels, "texture", where + "tracking_levels.");
  if (out.image_noise_sigma < 0.0 || out.residual_level < 0.0 || out.texture_level < 0.0) {
    m.Fail(where + "image_noise_sigma and tracking_levels must not be negative");
  }

  const std::string dir = MapDir(i);
  const std::string in_map = " (map " + std::to_string(i) + ")";
  const auto time = arrays.Get<int64_t>(dir + "keyframe_time", {K, 2});
  const auto pose = arrays.Get<double>(dir + "keyframe_pose", {K, 7});
  const auto brightness = arrays.Get<double>(dir + "keyframe_brightness", {K, 3});
  const auto error_model = arrays.Get<double>(dir + "keyframe_error_model", {K, 6});
  const auto levels = arrays.Get<int32_t>(dir + "keyframe_levels", {K, 2});
  const auto signature = arrays.Get<double>(dir + "keyframe_signature", {K, 3});
  const auto thumbnail_size = arrays.Get<int32_t>(dir + "keyframe_thumbnail_size", {K, 2});
  const auto thumbnails = arrays.Get<float>(dir + "keyframe_thumbnail", {T});
  const auto covisibility_offsets = arrays.Get<int32_t>(dir + "keyframe_covisibility_offsets", {K + 1});
  const auto covisibility = arrays.Get<int32_t>(dir + "keyframe_covisibility", {C});
  CheckOffsets(m, covisibility_offsets, C, dir + "keyframe_covisibility_offsets");
  const auto images = arrays.Get<uint16_t>(dir + "keyframe_image", {K, camera.height, camera.width});
  const size_t pixels = static_cast<size_t>(camera.width) * camera.height;
  size_t thumbnail_at = 0;
  for (int k = 0; k < K; ++k) {
    const std::string kf_where = "keyframe " + std::to_string(k) + in_map;
    auto kf = std::make_unique<Keyframe>();
    kf->id = k;
    kf->frame_index = static_cast<int>(std::clamp<int64_t>(time[2 * k], -1, std::numeric_limits<int>::max()));
    if (kf->frame_index != time[2 * k]) m.Fail(kf_where + ": frame index out of range");
    kf->t_ns = time[2 * k + 1];
    const double* p = &pose[7 * k];
    for (int j = 0; j < 7; ++j)
      if (!std::isfinite(p[j])) m.Fail(kf_where + ": the pose is not finite");
    const Eigen::Quaterniond q(p[3], p[0], p[1], p[2]);
    if (std::abs(q.squaredNorm() - 1.0) > 1e-9) m.Fail(kf_where + ": the pose's quaternion is not of unit length");
    kf->cam_from_world = SE3d(SO3d::FromUnitQuaternion(q), Eigen::Vector3d(p[4], p[5], p[6]));
    const double* b = &brightness[3 * k];
    if (!std::isfinite(b[0]) || !std::isfinite(b[1]) || !(b[2] > 0 && std::isfinite(b[2]))) {
      m.Fail(kf_where + ": brightness or exposure out of range");
    }
    kf->affine = {b[0], b[1]};
    kf->exposure = b[2];
    const double* e = &error_model[6 * k];
    for (int j = 0; j < 6; ++j)
      if (!std::isfinite(e[j])) m.Fail(kf_where + ": the error model is not finite");
    if (e[0] != 0 && e[0] != 1 && e[0] != 2) m.Fail(kf_where + ": unknown error model kind");
    if (!(e[1] > 0 && e[2] > 0 && e[3] > 0 && e[4] > 0) || (e[5] != 0 && e[5] != 1)) {
      m.Fail(kf_where + ": error model parameters out of range");
    }
    kf->error_model = {static_cast<RobustKind>(static_cast<int>(e[0])), e[1], e[2], e[3], e[4], e[5] == 1};
    kf->pyramid_levels = levels[2 * k];
    kf->most_pba_links = levels[2 * k + 1];
    const int div = kf->pyramid_levels >= 1 && kf->pyramid_levels <= kMaxPyramidLevels ? 1 << (kf->pyramid_levels - 1) : 0;
    if (div == 0 || camera.width % div != 0 || camera.height % div != 0) {
      m.Fail(kf_where + ": " + std::to_string(kf->pyramid_levels) + " pyramid levels do not fit the camera's size");
    }
    if (kf->most_pba_links < 0) m.Fail(kf_where + ": negative link count");
    kf->image = Image<uint16_t>(camera.width, camera.height);
    std::copy_n(images.begin() + k * pixels, pixels, kf->image.data());
    FrameSignature& s = kf->signature;
    s.texture = signature[3 * k];
    s.mean = signature[3 * k + 1];
    s.deviation = signature[3 * k + 2];
    if (!std::isfinite(s.texture) || !std::isfinite(s.mean) || !std::isfinite(s.deviation)) {
      m.Fail(kf_where + ": the signature is not finite");
    }
    const int tw = thumbnail_size[2 * k], th = thumbnail_size[2 * k + 1];
    if (tw < 0 || th < 0 || tw > 256 || th > 256 || static_cast<size_t>(tw) * th > thumbnails.size() - thumbnail_at) {
      m.Fail(kf_where + ": thumbnail size out of range");
    }
    if (tw * th > 0) {
      s.width = tw;
      s.height = th;
      s.thumbnail.assign(thumbnails.begin() + thumbnail_at, thumbnails.begin() + thumbnail_at + tw * th);
      if (!Finite(s.thumbnail.data(), tw * th)) m.Fail(kf_where + ": the thumbnail is not finite");
      thumbnail_at += static_cast<size_t>(tw) * th;
    }
    for (int32_t j = covisibility_offsets[k]; j < covisibility_offsets[k + 1]; ++j) {
      if (covisibility[j] < 0 || covisibility[j] >= K) m.Fail(kf_where + ": covisible keyframe out of range");
    }
    out.covisibility.emplace_back(covisibility.begin() + covisibility_offsets[k],
                                  covisibility.begin() + covisibility_offsets[k + 1]);
    out.map.RestoreKeyframe(std::move(kf));
  }
  if (thumbnail_at != thumbnails.size()) m.Fail(dir + "keyframe_thumbnail holds more values than its thumbnails");

  const auto host = arrays.Get<int32_t>(dir + "point_host", {P});
  const auto pixel = arrays.Get<float>(dir + "point_pixel", {P, 2});
  const auto idepth = arrays.Get<float>(dir + "point_idepth", {P});
  const auto created = arrays.Get<int32_t>(dir + "point_created", {P});
  const auto flags = arrays.Get<uint8_t>(dir + "point_flags", {P});
  const auto patch = arrays.Get<float>(dir + "point_patch", {P, kPatchFloats});
  const auto observation_offsets = arrays.Get<int32_t>(dir + "observation_offsets", {P + 1});
  const auto target = arrays.Get<int32_t>(dir + "observation_target", {O});
  const auto outlier = arrays.Get<uint8_t>(dir + "observation_outlier", {O});
  CheckOffsets(m, observation_offsets, O, dir + "observation_offsets");
  for (int id = 0; id < P; ++id) {
    const std::string pt_where = "point " + std::to_string(id) + in_map;
    Point p;
    p.id = id;
    p.host = host[id];
    if (p.host < 0 || p.host >= K) m.Fail(pt_where + ": host keyframe out of range");
    p.pixel = {pixel[2 * id], pixel[2 * id + 1]};
    if (!(p.pixel.x() >= 0 && p.pixel.x() <= camera.width - 1 && p.pixel.y() >= 0 && p.pixel.y() <= camera.height - 1)) {
      m.Fail(pt_where + ": pixel outside the image");
    }
    p.idepth = idepth[id];
    if (!(p.idepth > 0 && std::isfinite(p.idepth))) m.Fail(pt_where + ": inverse depth not positive and finite");
    p.created_at_keyframe = created[id];
    if (p.created_at_keyframe < 0) m.Fail(pt_where + ": negative creation count");
    if (flags[id] & ~(kRemoved | kPatchOk | kPatchBSpline)) m.Fail(pt_where + ": unknown flags");
    p.removed = flags[id] & kRemoved;
    p.patch_ok = flags[id] & kPatchOk;
    const float* f = &patch[kPatchFloats * id];
    if (!Finite(f, kPatchFloats)) m.Fail(pt_where + ": the patch is not finite");
    p.patch.center = {f[0], f[1]};
    std::copy_n(f + 2, kPatternSize, p.patch.value.begin());
    std::copy_n(f + 2 + kPatternSize, kPatternSize, p.patch.weight_g.begin());
    p.patch.interpolation = flags[id] & kPatchBSpline ? Interpolation::kBSpline : Interpolation::kBilinear;
    for (int32_t j = observation_offsets[id]; j < observation_offsets[id + 1]; ++j) {
      if (target[j] < 0 || target[j] >= K || target[j] == p.host) m.Fail(pt_where + ": observation target out of range");
      if (outlier[j] > 1) m.Fail(pt_where + ": observation flag out of range");
      p.observations.push_back({target[j], outlier[j] == 1});
    }
    out.map.RestorePoint(std::move(p));
  }
  return out;
}

}  // namespace

void WriteMapFile(const std::filesystem::path& path, const MapFile& file) {
  ZipWriter zip(path);
  json manifest = {{"format", kFormat},
                   {"version", kMapFileVersion},
                   {"created_by", file.created_by},
                   {"camera",
                    {{"width", file.camera.width},
                     {"height", file.camera.height},
                     {"fx", file.camera.fx},
                     {"fy", file.camera.fy},
                     {"cx", file.camera.cx},
                     {"cy", file.camera.cy}}},
                   {"options", file.options},
                   {"maps", json::array()},
                   {"arrays", json::object()}};
  ArrayWriter arrays(&zip, &manifest["arrays"]);
  for (size_t i = 0; i < file.maps.size(); ++i) {
    manifest["maps"].push_back(WriteMap(file.maps[i], i, file.camera, &arrays));
  }
  zip.Add(kManifest, manifest.dump(1) + "\n");
  zip.Close();
}

MapFile ReadMapFile(const std::filesystem::path& path) {
  const ZipReader zip(path);
  if (!zip.Has(kManifest)) throw InputError(path.string() + ": not a dsm map file (no " + kManifest + ")");
  json root;
  try {
    root = json::parse(zip.Read(kManifest));
  } catch (const json::exception& e) {
    throw InputError(path.string() + ": " + kManifest + " is not valid JSON (" + e.what() + ")");
  }
  const Manifest m(path.string(), std::move(root));
  if (!m.root().is_object() || !m.root().contains("format") || m.root()["format"] != kFormat) {
    m.Fail("not a dsm map file (the manifest's format is not \"" + std::string(kFormat) + "\")");
  }
  const int64_t version = m.Int(m.root(), "version", "", 0, std::numeric_limits<int>::max());
  MapFile file;
  file.created_by = m.String(m.root(), "created_by", "");
  if (version != kMapFileVersion) {
    m.Fail("format version " + std::to_string(version) + " (written by " + file.created_by + "); this dsm " +
           kVersion + " reads version " + std::to_string(kMapFileVersion));
  }
  file.camera = ReadCamera(m);
  file.options = m.String(m.root(), "options", "");
  const json& maps = m.At(m.root(), "maps", "");
  if (!maps.is_array()) m.Fail("maps must be a list");
  const ArrayReader arrays(&zip, &m);
  for (size_t i = 0; i < maps.size(); ++i) file.maps.push_back(ReadMap(m, arrays, maps[i], i, file.camera));
  return file;
}

std::string CameraText(const PinholeCamera& c) {
  std::ostringstream out;
  out << c.width << "x" << c.height << " pinhole, fx " << c.fx << " fy " << c.fy << " cx " << c.cx << " cy " << c.cy;
  return out.str();
}

std::vector<StoredMap> MapsToTakeUp(const std::filesystem::path& path, MapFile file, const PinholeCamera& camera) {
  const PinholeCamera& c = file.camera;
  const auto near = [](double a, double b) { return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(b)); };
  if (c.width != camera.width || c.height != camera.height || !near(c.fx, camera.fx) || !near(c.fy, camera.fy) ||
      !near(c.cx, camera.cx) || !near(c.cy, camera.cy)) {
    throw InputError(path.string() + ": the map was made with another camera (" + CameraText(c) +
                     "; this one is " + CameraText(camera) + ")");
  }
  std::vector<StoredMap> maps;
  for (StoredMap& stored : file.maps)
    if (stored.map.NumKeyframes() > 0) maps.push_back(std::move(stored));
  if (maps.empty()) throw InputError(path.string() + ": the map file holds no map with keyframes");
  return maps;
}

std::string DescribeMapFile(const std::filesystem::path& path, const MapFile& file) {
  std::ostringstream out;
  out << "map file:   " << path.string() << "\n";
  out << "format:     " << kFormat << " version " << kMapFileVersion << ", written by " << file.created_by << "\n";
  const PinholeCamera& c = file.camera;
  out << "camera:     " << CameraText(c) << "\n";
  out << "maps:       " << file.maps.size() << "\n";
  for (size_t i = 0; i < file.maps.size(); ++i) {
    const Map& map = file.maps[i].map;
    int observations = 0, first = -1, last = -1;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (int id = 0; id < map.NumPoints(); ++id) {
      const Point& p = map.point(id);
      if (p.removed) continue;
      observations += p.NumGoodObservations();
      const Eigen::Vector3d x = map.keyframe(p.host).WorldFromCam() * (c.Unproject(p.pixel.x(), p.pixel.y()) / p.idepth);
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    for (int k = 0; k < map.NumKeyframes(); ++k) {
      const int f = map.keyframe(k).frame_index;
      first = first < 0 ? f : std::min(first, f);
      last = std::max(last, f);
    }
    out << "map " << i << ":      " << map.NumKeyframes() << " keyframes (frames " << first << "-" << last << "), "
        << map.NumLivePoints() << " points (" << map.NumPoints() - map.NumLivePoints() << " removed), " << observations
        << " inlier observations, " << (map.interpolation() == Interpolation::kBSpline ? "B-spline" : "bilinear")
        << " sampling\n";
    if (map.NumLivePoints() > 0) {
      out << "  bounds:   [" << lo.x() << ", " << lo.y() << ", " << lo.z() << "] - [" << hi.x() << ", " << hi.y() << ", "
          << hi.z() << "] (the map's units)\n";
    }
  }
  return out.str();
}

}  // namespace dsm
