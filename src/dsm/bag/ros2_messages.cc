// SPDX-License-Identifier: MIT
#include "dsm/bag/ros2_messages.h"

#include "dsm/bag/cdr_writer.h"

namespace dsm {

std::vector<uint8_t> CdrImage(int64_t t_ns, const std::string& frame, const Image<uint8_t>& image) {
  CdrWriter w;
  w.Header(t_ns, frame);
  w.U32(static_cast<uint32_t>(image.height()));
  w.U32(static_cast<uint32_t>(image.width()));
  w.String("mono8");
  w.U8(0);
  w.U32(static_cast<uint32_t>(image.width()));
  std::vector<uint8_t> pixels;
  for (int y = 0; y < image.height(); ++y) pixels.insert(pixels.end(), image.Row(y), image.Row(y) + image.width());
  w.Bytes(pixels.data(), pixels.size());
  return w.Take();
}

std::vector<uint8_t> CdrCameraInfo(int64_t t_ns, const std::string& frame, int width, int height, double fx, double fy,
                                   double cx, double cy, const std::vector<double>& distortion) {
  CdrWriter w;
  w.Header(t_ns, frame);
  w.U32(static_cast<uint32_t>(height));
  w.U32(static_cast<uint32_t>(width));
  w.String("plumb_bob");
  w.Count(distortion.size());
  for (double d : distortion) w.F64(d);
  for (double v : {fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0}) w.F64(v);
  for (double v : {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) w.F64(v);
  for (double v : {fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0}) w.F64(v);
  w.U32(0);
  w.U32(0);
  for (int i = 0; i < 4; ++i) w.U32(0);  // roi: the whole image
  w.U8(0);
  return w.Take();
}

}  // namespace dsm
