// SPDX-License-Identifier: MIT
// The option registry: every option of SystemOptions a user can set, declared once with its key
// (section.name) and a one-line description, above system/ so that the layers below it need no
// option of the whole system. Option files are a YAML mapping of sections to values, e.g.
//   window: {temporal_keyframes: 5}
//   pba: {levels: 2}
//   robust: {function: huber}
// Unknown sections or keys and values of the wrong type are rejected with a message naming the
// file and the key.
#pragma once

#include <filesystem>
#include <string>

#include "dsm/system/options.h"

namespace dsm {

void ApplyOptionsYaml(const std::filesystem::path& path, SystemOptions* options);
// The same from text (YAML, or JSON, which is YAML too); `source` names it in messages.
void ApplyOptionsText(const std::string& text, const std::string& source, SystemOptions* options);
// Every option a file can set, with its value in `options` and a one-line description, as an
// option file: ApplyOptionsText of it gives `options` back.
std::string OptionsYaml(const SystemOptions& options);

}  // namespace dsm
