// JSON text from users into a document, safely: nlohmann-json's SAX parser (iterative: no recursion a
// request could drive) into our own builder, which refuses nesting deeper than `max_depth` while parsing,
// and names the field of a number that overflows a double (1e400) instead of failing without a name.
// Invalid JSON, including invalid UTF-8 anywhere in a string, is a SpecError "invalid_json".
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace granulab::api {

/// The deepest nesting of objects and arrays a request may hold.
constexpr std::size_t kMaxJsonDepth = 64;

/// Throws SpecError: "invalid_json" (field ""), "too_deep" (field = where the limit was crossed) or
/// "out_of_range" (field = the dotted path of a number that does not fit a double).
nlohmann::json parse_bounded_json(const std::string& text, std::size_t max_depth = kMaxJsonDepth);

}  // namespace granulab::api
