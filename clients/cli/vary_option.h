// `granulab sweep --vary KEY=V1,V2,...`: the options into the sweep request's "vary" object
// ({"dotted.key": [values]}, api/sweep.h). Each value is JSON (10e3, true, "a,b", [1,1,0], {"k": 1}) or, when it
// is not JSON, plain text (fcc); the values are split at the commas outside brackets, braces and quotes, so a
// list is one value: `loading.axis=[1,1,0],[1,1,1]` is two points. That is the only reading of a comma, so no
// option means two things; a list of lists of values (`key=[[1,1,0],[1,1,1]]`) is not taken as the values,
// since it is also one value (a list of lists). Header-only, so that the clients' tests test this very parser.
// A malformed option is an std::invalid_argument saying what is wrong and showing the syntax with examples.
#pragma once

#include <cctype>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace granulab::cli {

/// What every --vary error ends with: the syntax and examples (shell quotes keep [ ] and " as typed).
inline const char* vary_syntax() {
  return "--vary takes KEY=V1,V2,...: a dotted spec field (docs/spec.md), '=', then its values separated by commas;\n"
         "each value is JSON (a number, true, \"text\", a list [1,1,0]) or else plain text, and commas inside\n"
         "[ ], { } or \"...\" belong to the value. Quote the option in the shell. For example:\n"
         "  --vary loading.confining_pressure=10e3,30e3,60e3\n"
         "  --vary crystal.lattice=sc,fcc\n"
         "  --vary 'loading.axis=[1,1,0],[1,1,1]'\n"
         "  --vary 'output.snapshot_strains=[0,0.001],[0,0.002,0.004]'\n"
         "(--zip pairs the lists value by value instead of running every combination)";
}

namespace vary_detail {

[[noreturn]] inline void refuse(const std::string& option, const std::string& what) {
  throw std::invalid_argument("--vary '" + option + "': " + what + "\n" + vary_syntax());
}

inline std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

// A spec field's dotted name: words of letters, digits and '_', joined by single dots.
inline bool is_dotted_key(const std::string& key) {
  bool word_start = true;
  for (const char c : key) {
    if (c == '.') {
      if (word_start) return false;
      word_start = true;
      continue;
    }
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    word_start = false;
  }
  return !word_start;
}

}  // namespace vary_detail

/// The values of one option's text after '=' ("10e3,30e3", "[1,1,0],[1,1,1]", "sc,\"a,b\""); `option` is the
/// whole option, for the message.
inline nlohmann::json parse_vary_values(const std::string& option, const std::string& text) {
  using vary_detail::refuse;
  // Split at the commas outside [ ], { } and "..." (a backslash escapes inside quotes, as in JSON).
  std::vector<std::string> items;
  std::string closers;  // the closing brackets owed, innermost last
  bool quoted = false, escaped = false;
  std::size_t start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') quoted = false;
    } else if (c == '"') {
      quoted = true;
    } else if (c == '[' || c == '{') {
      closers.push_back(c == '[' ? ']' : '}');
    } else if (c == ']' || c == '}') {
      if (closers.empty() || closers.back() != c)
        refuse(option,
               std::string("the '") + c + "' at character " + std::to_string(i + 1) + " of the values " +
                   (closers.empty() ? "closes nothing" : "should be a '" + closers.substr(closers.size() - 1) + "'"));
      closers.pop_back();
    } else if (c == ',' && closers.empty()) {
      items.push_back(text.substr(start, i - start));
      start = i + 1;
    }
  }
  if (quoted) refuse(option, "a '\"' is never closed");
  if (!closers.empty()) refuse(option, "a '" + std::string(1, closers.back() == ']' ? '[' : '{') + "' is never closed");
  items.push_back(text.substr(start));

  nlohmann::json values = nlohmann::json::array();
  for (std::size_t n = 0; n < items.size(); ++n) {
    const std::string item = vary_detail::trimmed(items[n]);
    const std::string which = "value " + std::to_string(n + 1) + " of " + std::to_string(items.size());
    if (item.empty()) refuse(option, which + " is empty (two commas together, or one at an end)");
    nlohmann::json parsed = nlohmann::json::parse(item, nullptr, false);
    if (item.front() == '[' || item.front() == '{' || item.front() == '"') {
      if (parsed.is_discarded()) refuse(option, which + ", " + item + ", is not JSON");
      values.push_back(std::move(parsed));
    } else if (item.find_first_of("[]{}\"") != std::string::npos) {
      refuse(option, which + ", " + item +
                         ", is text with brackets or quotes in it: write a list whole, "
                         "a value per comma, or text in quotes");
    } else {
      values.push_back(parsed.is_discarded() ? nlohmann::json(item) : std::move(parsed));
    }
  }
  return values;
}

/// Every --vary option into {"dotted.key": [values]}; with `zip` the lists must be as long as each other.
inline nlohmann::json parse_vary(const std::vector<std::string>& options, bool zip) {
  using vary_detail::refuse;
  nlohmann::json vary = nlohmann::json::object();
  std::string first_key;
  for (const std::string& option : options) {
    const auto eq = option.find('=');
    if (eq == std::string::npos) refuse(option, "no '=' between the field and its values");
    const std::string key = vary_detail::trimmed(option.substr(0, eq));
    if (key.empty()) refuse(option, "no field before the '='");
    if (!vary_detail::is_dotted_key(key))
      refuse(option, "'" + key + "' is not a dotted spec field (words of letters, digits and '_' joined by '.')");
    if (vary_detail::trimmed(option.substr(eq + 1)).empty()) refuse(option, "no values after the '='");
    if (vary.contains(key)) refuse(option, "'" + key + "' is varied twice: give all its values in one --vary");
    vary[key] = parse_vary_values(option, option.substr(eq + 1));
    if (first_key.empty()) first_key = key;
    if (zip && vary[key].size() != vary[first_key].size())
      refuse(option, "--zip pairs the lists value by value, so they must be as long as each other: '" + first_key +
                         "' has " + std::to_string(vary[first_key].size()) + " values, '" + key + "' has " +
                         std::to_string(vary[key].size()));
  }
  return vary;
}

}  // namespace granulab::cli
