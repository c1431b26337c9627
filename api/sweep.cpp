#include "api/sweep.h"

#include <algorithm>

#include "api/spec_error.h"

namespace granulab::api {

namespace {

using nlohmann::json;

// Sets the field at a dotted key, creating the sections on the way ("loading.confining_pressure").
void set_dotted(json& doc, const std::string& key, const json& value) {
  json* node = &doc;
  std::size_t start = 0;
  for (std::size_t dot; (dot = key.find('.', start)) != std::string::npos; start = dot + 1) {
    json& section = (*node)[key.substr(start, dot - start)];
    if (section.is_null()) section = json::object();
    if (!section.is_object())
      throw SpecError("invalid_value", "vary." + key, "'" + key + "' is not inside an object of the spec");
    node = &section;
  }
  (*node)[key.substr(start)] = value;
}

std::string short_text(const json& v) {
  const std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

}  // namespace

Sweep parse_sweep(const json& request, std::size_t max_jobs, std::size_t max_bytes) {
  if (!request.is_object())
    throw SpecError("wrong_type", "", "a sweep must be a JSON object {\"spec\", \"vary\", \"mode\", \"label\"}");
  for (const auto& [key, value] : request.items())
    if (key != "spec" && key != "vary" && key != "mode" && key != "label")
      throw SpecError("unknown_field", key, "unknown field '" + key + "' (a sweep has spec, vary, mode, label)");
  Sweep s;
  if (!request.contains("spec"))
    throw SpecError("missing", "spec", "'spec' (the base spec every point starts from) is required");
  s.base = request["spec"];
  if (!s.base.is_object()) throw SpecError("wrong_type", "spec", "'spec' must be an object (the base spec)");
  s.mode = request.contains("mode") && request["mode"].is_string() ? request["mode"].get<std::string>() : "product";
  if (request.contains("mode") && !request["mode"].is_string())
    throw SpecError("wrong_type", "mode", "'mode' must be \"product\" or \"zip\"");
  if (s.mode != "product" && s.mode != "zip")
    throw SpecError("invalid_value", "mode", "'mode' must be \"product\" or \"zip\", got '" + s.mode + "'");
  if (request.contains("label") && !request["label"].is_string())
    throw SpecError("wrong_type", "label", "'label' must be a string");
  s.label = request.value("label", std::string());
  if (std::count_if(s.label.begin(), s.label.end(),
                    [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }) > 200)
    throw SpecError("out_of_range", "label", "'label' must be at most 200 characters");
  s.vary = request.value("vary", json::object());
  if (!s.vary.is_object() || s.vary.empty())
    throw SpecError("wrong_type", "vary",
                    "'vary' must be an object of dotted keys and lists of values, e.g. "
                    "{\"loading.confining_pressure\": [10e3, 30e3]}");
  std::vector<std::string> keys;
  std::size_t count = s.mode == "zip" ? 0 : 1, length = 0;
  for (const auto& [key, values] : s.vary.items()) {
    if (key == "experiment")
      throw SpecError("invalid_value", "vary.experiment", "a sweep varies one experiment's fields, not the experiment");
    if (!values.is_array() || values.empty())
      throw SpecError("wrong_type", "vary." + key, "'vary." + key + "' must be a non-empty list of values");
    if (s.mode == "zip" && !keys.empty() && values.size() != length)
      throw SpecError("invalid_value", "vary." + key,
                      "with mode \"zip\" every list must be as long as the first (" + std::to_string(length) +
                          "); 'vary." + key + "' has " + std::to_string(values.size()));
    length = values.size();
    count = s.mode == "zip" ? length : count * values.size();
    if (count > max_jobs)
      throw SpecError(
          "out_of_range", "vary",
          "the sweep would make more than " + std::to_string(max_jobs) + " jobs (max_jobs_per_sweep); split it");
    keys.push_back(key);
  }
  // What storing it would cost, before any point is made: each job keeps its own spec, so a sweep stores
  // about its base spec's size once per point (a 600 KB spec in 1000 points was 600 MB and 29 s of work).
  const std::size_t base_bytes = s.base.dump().size();
  if (base_bytes * count > max_bytes)
    throw SpecError("out_of_range", "vary",
                    "the sweep would store " + std::to_string(count) + " specs of about " + std::to_string(base_bytes) +
                        " bytes each, over the limit of " + std::to_string(max_bytes) +
                        " bytes per sweep (max_sweep_bytes): fewer points, or a smaller base spec");
  // Every point, validated: the first bad one names its key and value.
  std::size_t stored = 0;
  for (std::size_t n = 0; n < count; ++n) {
    json doc = s.base, values = json::object();
    std::size_t rest = n;
    for (std::size_t k = keys.size(); k-- > 0;) {  // the last key varies fastest
      const json& list = s.vary[keys[k]];
      const std::size_t i = s.mode == "zip" ? n : rest % list.size();
      if (s.mode != "zip") rest /= list.size();
      set_dotted(doc, keys[k], list[i]);
      values[keys[k]] = list[i];
    }
    try {
      s.points.push_back({values, parse_spec(doc)});
    } catch (const SpecError& e) {
      // The base spec's own fault when it fails alone; otherwise the varied key the error is about: the
      // field itself, one inside it, or the section a key that does not exist was put in ("bogus.x").
      try {
        parse_spec(s.base);
      } catch (const SpecError& base) {
        throw SpecError(base.code, base.field.empty() ? "spec" : "spec." + base.field,
                        std::string("the base spec: ") + base.what());
      }
      std::string culprit;
      for (const std::string& k : keys)
        if (e.field == k || e.field.rfind(k + ".", 0) == 0 || e.field.rfind(k + "[", 0) == 0 || e.field.empty() ||
            k.rfind(e.field + ".", 0) == 0 || k.rfind(e.field + "[", 0) == 0)
          if (culprit.empty()) culprit = k;
      if (culprit.empty()) culprit = keys.front();
      throw SpecError(e.code, "vary." + culprit,
                      "'vary." + culprit + "' value " + short_text(values[culprit]) + ": " + e.what());
    }
    // Exactly, as they will be stored (defaults filled in): the estimate above can be short of it.
    stored += s.points.back().spec.normalized.dump().size();
    if (stored > max_bytes)
      throw SpecError("out_of_range", "vary",
                      "the sweep's first " + std::to_string(n + 1) + " of " + std::to_string(count) +
                          " specs already hold " + std::to_string(stored) + " bytes, over the limit of " +
                          std::to_string(max_bytes) + " bytes per sweep (max_sweep_bytes)");
  }
  return s;
}

}  // namespace granulab::api
