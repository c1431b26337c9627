#include "api/spec_docs.h"

#include "api/headline_json.h"

#include <map>
#include <sstream>

#include "api/spec.h"

namespace granulab::api {

namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Describes each visited field; list items are visited once, as "key[].field".
class FieldDescriber : public ParameterVisitor {
 public:
  nlohmann::json fields = nlohmann::json::array();

  void section(const char* name) override { section_ = name; }
  void number(const char* key, double& value, Range r, const char* unit, const char* meaning) override {
    bounded(add(key, "number", value, unit, meaning), r);
  }
  void integer(const char* key, int& value, long lo, long hi, const char* meaning) override {
    add(key, "integer", value, "-", meaning).update({{"minimum", lo}, {"maximum", hi}});
  }
  void choice(const char* key, std::string& value, const std::vector<std::string>& allowed,
              const char* meaning) override {
    add(key, "string", value, "", meaning)["choices"] = allowed;
  }
  void text(const char* key, std::string& value, std::size_t max_length, const char* meaning) override {
    add(key, "string", value, "", meaning)["max_length"] = max_length;
  }
  void numbers(const char* key, std::vector<double>& values, Range r, std::size_t max_items, const char* unit,
               const char* meaning) override {
    bounded(add(key, "array of numbers", values, unit, meaning), r)["max_items"] = max_items;
  }
  void grain_ids(const char* key, std::vector<GrainId>& values, std::uint32_t last, const char* last_is,
                 std::size_t max_items, const char* meaning) override {
    (void)values, (void)last;
    add(key, "array of grain ids", nlohmann::json::array(), "-", meaning)
        .update({{"minimum", 0}, {"maximum_is", last_is}, {"max_items", max_items}});
  }
  std::size_t begin_list(const char* key, std::size_t max_items, const char* meaning) override {
    add(key, "array of objects", nlohmann::json::array(), "", meaning)["max_items"] = max_items;
    list_ = key;
    return 1;
  }
  void begin_item(std::size_t) override { in_item_ = true; }
  void end_item() override { in_item_ = false; }
  void end_list() override { list_.clear(); }
  void require(bool, const char*, const std::string&) override {}

 private:
  // A bound that depends on another field is stated in words ("maximum_is"), never as the default's number.
  static nlohmann::json& bounded(nlohmann::json& f, const Range& r) {
    f.update({{"minimum", r.lo}, {"exclusive_minimum", r.lo_open}});
    if (r.hi_is) f["maximum_is"] = r.hi_is;
    else f["maximum"] = r.hi;
    return f;
  }
  nlohmann::json& add(const char* key, const char* type, nlohmann::json value, const char* unit, const char* meaning) {
    std::string name = in_item_ ? list_ + "[]." + key : key;
    if (!section_.empty()) name = section_ + "." + name;
    fields.push_back({{"field", name}, {"type", type}, {"default", value}, {"unit", unit}, {"meaning", meaning}});
    return fields.back();
  }
  std::string section_, list_;
  bool in_item_ = false;
};

std::string allowed_text(const nlohmann::json& f) {
  if (f.contains("choices")) {
    std::string s;
    for (const auto& c : f["choices"]) s += (s.empty() ? "" : ", ") + ("`" + c.get<std::string>() + "`");
    return s;
  }
  if (f.contains("max_length")) return "at most " + std::to_string(f["max_length"].get<std::size_t>()) + " characters";
  if (!f.contains("minimum")) return "";
  const bool open = f.value("exclusive_minimum", false);
  const std::string hi = f.contains("maximum") ? fmt(f["maximum"].get<double>()) : f["maximum_is"].get<std::string>();
  std::string s = std::string(open ? "(" : "[") + fmt(f["minimum"].get<double>()) + ", " + hi + "]";
  if (f.contains("max_items")) s += ", at most " + std::to_string(f["max_items"].get<std::size_t>()) + " values";
  return s;
}

std::string default_text(const nlohmann::json& d) {
  if (d.is_string()) return d.get<std::string>().empty() ? "\"\"" : "`" + d.get<std::string>() + "`";
  if (d.is_number_float()) return fmt(d.get<double>());
  if (d.is_array() && !d.empty() && d[0].is_number_float()) {
    std::string s;
    for (const auto& x : d) s += (s.empty() ? "" : ", ") + fmt(x.get<double>());
    return "[" + s + "]";
  }
  return d.dump();
}

}  // namespace

nlohmann::json experiments_json() {
  nlohmann::json list = nlohmann::json::array();
  for (const ExperimentType& t : experiment_types()) {
    FieldDescriber d;
    JobFields job;
    job.experiment = t.name;
    visit_job_fields(d, job);
    std::unique_ptr<Experiment> e = t.make();
    e->parameters(d);
    nlohmann::json columns = nlohmann::json::array();
    for (const CurveColumn& c : e->curve_columns())
      columns.push_back({{"name", c.name}, {"unit", c.unit}, {"meaning", c.meaning}});
    list.push_back({{"name", t.name},
                    {"title", t.title},
                    {"fields", d.fields},
                    {"curve_columns", columns},
                    {"headline", headline_json(e->headline())}});
  }
  return {{"experiments", list}};
}

namespace {

// One field of experiments_json() as a JSON Schema; null is allowed everywhere (it means the default).
nlohmann::json field_schema(const nlohmann::json& f, const nlohmann::json& items) {
  using nlohmann::json;
  const std::string type = f["type"];
  const std::string unit = f.value("unit", "");
  // A bound that depends on another field is in the words, not a false maximum.
  const std::string depends = f.contains("maximum_is") ? "; at most " + f["maximum_is"].get<std::string>() : "";
  json s = {{"description",
             f["meaning"].get<std::string>() + (unit.empty() || unit == "-" ? "" : " (" + unit + ")") + depends},
            {"default", f["default"]}};
  if (!unit.empty()) s["x-unit"] = unit;
  auto bounds = [&](json& target) {
    if (!f.contains("minimum")) return;
    if (f.value("exclusive_minimum", false)) target["exclusiveMinimum"] = f["minimum"];
    else target["minimum"] = f["minimum"];
    if (f.contains("maximum")) target["maximum"] = f["maximum"];
  };
  if (type == "number" || type == "integer") {
    s["type"] = json::array({type, "null"});
    bounds(s);
  } else if (type == "string") {
    s["type"] = json::array({"string", "null"});
    if (f.contains("choices")) s["enum"] = f["choices"];
    if (f.contains("max_length")) s["maxLength"] = f["max_length"];
  } else {
    json item = {{"type", type == "array of numbers" ? "number" : type == "array of grain ids" ? "integer" : "object"}};
    if (type == "array of objects") item = items;
    else bounds(item);
    s["type"] = json::array({"array", "null"});
    s["items"] = item;
    if (f.contains("max_items")) s["maxItems"] = f["max_items"];
  }
  return s;
}

}  // namespace

nlohmann::json spec_schemas_json() {
  using nlohmann::json;
  json schemas = json::object(), one_of = json::array();
  const json described = experiments_json();  // named: a range over a temporary's member would dangle
  for (const json& e : described["experiments"]) {
    const std::string name = e["name"];
    json spec = {{"type", "object"},
                 {"title", name},
                 {"description", e["title"]},
                 {"additionalProperties", false},
                 {"properties", json::object()}};
    // List items first ("a.b[].c" fields), so their lists can take them.
    std::map<std::string, json> items;
    for (const json& f : e["fields"]) {
      const std::string field = f["field"];
      const auto brackets = field.find("[].");
      if (brackets == std::string::npos) continue;
      json& item = items[field.substr(0, brackets)];
      if (item.is_null()) item = {{"type", "object"}, {"additionalProperties", false}, {"properties", json::object()}};
      item["properties"][field.substr(brackets + 3)] = field_schema(f, json());
    }
    for (const json& f : e["fields"]) {
      const std::string field = f["field"];
      if (field.find("[].") != std::string::npos) continue;
      const auto dot = field.find('.');
      json schema = field_schema(f, items[field]);
      if (field == "experiment") {
        // Which schema a spec follows; only the default experiment (the registry's first) may leave it
        // out or give null.
        if (name == described["experiments"][0]["name"]) {
          schema = {{"enum", json::array({name, nullptr})},
                    {"default", name},
                    {"description", "the experiment (left out or null: this one, the default)"}};
        } else {
          schema = {{"const", name}, {"description", "the experiment"}};
          spec["required"] = json::array({"experiment"});
        }
        spec["properties"]["experiment"] = schema;
        continue;
      }
      if (dot == std::string::npos) {
        spec["properties"][field] = schema;
        continue;
      }
      json& section = spec["properties"][field.substr(0, dot)];
      if (section.is_null())
        section = {
            {"type", json::array({"object", "null"})}, {"additionalProperties", false}, {"properties", json::object()}};
      section["properties"][field.substr(dot + 1)] = schema;
    }
    schemas["Spec_" + name] = spec;
    one_of.push_back({{"$ref", "#/components/schemas/Spec_" + name}});
  }
  schemas["Spec"] = {{"description", "an experiment's spec (docs/spec.md); a field left out or null takes its default"},
                     {"oneOf", one_of}};
  return schemas;
}

std::string experiments_markdown() {
  std::string out =
      "# The spec, field by field\n\n"
      "Generated from the experiment registry (`granulab experiments --markdown`); a test keeps this file\n"
      "equal to that output, so it is always what the code reads. Units are SI (`a`: grain sizes; `-`: none).\n"
      "Every field has a default, so `{\"experiment\": \"<name>\"}` is a complete spec; unknown fields and values\n"
      "outside the allowed range are rejected with a message that names the field.\n";
  const nlohmann::json description = experiments_json();
  for (const nlohmann::json& e : description["experiments"]) {
    out += "\n## `" + e["name"].get<std::string>() + "`\n\n" + e["title"].get<std::string>() + ".\n\n";
    out += "| field | default | allowed | unit | meaning |\n| --- | --- | --- | --- | --- |\n";
    for (const nlohmann::json& f : e["fields"])
      out += "| `" + f["field"].get<std::string>() + "` | " + default_text(f["default"]) + " | " + allowed_text(f) +
             " | " + f["unit"].get<std::string>() + " | " + f["meaning"].get<std::string>() + " |\n";
    out +=
        "\nCurve columns (`curve.csv`, `GET /v1/jobs/{id}/curve`):\n\n| column | unit | meaning |\n| --- | --- | --- "
        "|\n";
    for (const nlohmann::json& c : e["curve_columns"])
      out += "| `" + c["name"].get<std::string>() + "` | " + c["unit"].get<std::string>() + " | " +
             c["meaning"].get<std::string>() + " |\n";
  }
  return out;
}

}  // namespace granulab::api
