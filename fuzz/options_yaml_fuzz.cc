// SPDX-License-Identifier: MIT
// Option files (`dsm run --options FILE`): sections of keys, then SystemOptions::Validate.
#include "dsm/config/option_registry.h"
#include "dsm/util/check.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::filesystem::path path = dsm::fuzz::Scratch() / "options.yaml";
  dsm::fuzz::WriteFile(path, {reinterpret_cast<const char*>(data), size});
  dsm::SystemOptions options;
  try {
    dsm::ApplyOptionsYaml(path, &options);
  } catch (const dsm::InputError& e) {
    dsm::fuzz::Report(std::string("rejected: ") + e.what());
    return 0;
  }
  // Accepted options must pass the checks a run makes before it starts.
  try {
    options.Validate();
  } catch (const dsm::InputError& e) {
    DSM_CHECK(false, std::string("accepted options fail Validate: ") + e.what());
  }
  dsm::fuzz::Report("accepted");
  return 0;
}
