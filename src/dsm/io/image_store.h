// SPDX-License-Identifier: MIT
// Where a dataset's images live: a folder of files, or a zip archive (TUM monoVO images.zip).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "dsm/image/image.h"

namespace dsm {

class ImageStore {
 public:
  virtual ~ImageStore() = default;
  // Loads image `name` as 8-bit grey; throws InputError naming the file when it cannot.
  virtual Image<uint8_t> Load(const std::string& name) const = 0;
  // Asks the system to bring image `name`'s file into memory ahead of its Load, without waiting
  // (a hint: nothing is reported; a no-op where there is nothing to ask).
  virtual void Prefetch(const std::string& /*name*/) const {}
  // Names of the image files (png, jpg, jpeg, pgm, ppm, bmp, tif, tiff), sorted.
  virtual std::vector<std::string> List() const = 0;
  virtual std::string Describe() const = 0;
};

std::shared_ptr<ImageStore> MakeFolderStore(const std::filesystem::path& folder);
std::shared_ptr<ImageStore> MakeZipStore(const std::filesystem::path& zip_file);

}  // namespace dsm
