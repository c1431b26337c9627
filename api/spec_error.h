// A validation error that names the offending field (dotted path, e.g. "grain.edge_spheres").
#pragma once

#include <stdexcept>
#include <string>

namespace granulab::api {

struct SpecError : std::runtime_error {
  SpecError(std::string code, std::string field, const std::string& message)
      : std::runtime_error(message), code(std::move(code)), field(std::move(field)) {}
  std::string code;   ///< machine-readable: invalid_json, unknown_field, wrong_type, out_of_range, ...
  std::string field;  ///< dotted path of the field, empty for the whole document
};

}  // namespace granulab::api
