// Files of the source tree compiled into granulabd (cmake/embed_files.cmake): the API document and the
// web page, so a daemon serves them from wherever it is installed.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

namespace granulab::server {

/// The text of the embedded file `name` (its path in the repository, e.g. "docs/openapi.json").
std::optional<std::string_view> embedded_file(std::string_view name);
/// Every embedded file's name.
std::vector<std::string_view> embedded_names();

}  // namespace granulab::server
