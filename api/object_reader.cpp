#include "api/object_reader.h"

#include <algorithm>

#include <cmath>
#include <cstdint>
#include <sstream>

namespace granulab::api {

namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string type_name(const nlohmann::json& j) { return j.type_name(); }

}  // namespace

ObjectReader::ObjectReader(const nlohmann::json& parent, const std::string& key, const std::string& path)
    : path_(path) {
  const auto it = parent.find(key);
  if (it == parent.end() || it->is_null()) {
    object_ = nlohmann::json::object();
  } else if (!it->is_object()) {
    throw SpecError("wrong_type", path, "'" + path + "' must be an object, got " + type_name(*it));
  } else {
    object_ = *it;
  }
}

ObjectReader::ObjectReader(const nlohmann::json& document) {
  if (!document.is_object())
    throw SpecError("wrong_type", "", "the spec must be a JSON object, got " + type_name(document));
  object_ = document;
}

const nlohmann::json* ObjectReader::find(const std::string& key) {
  seen_.insert(key);
  const auto it = object_.find(key);
  return it == object_.end() || it->is_null() ? nullptr : &*it;
}

double ObjectReader::number(const std::string& key, double fallback, double lo, double hi, bool lo_open) {
  const std::string range = (lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + "]";
  double v = fallback;
  if (const nlohmann::json* j = find(key)) {
    if (!j->is_number())
      throw SpecError("wrong_type", field(key),
                      "'" + field(key) + "' must be a number in " + range + ", got " + type_name(*j));
    v = j->get<double>();
  }
  if (!std::isfinite(v) || v > hi || v < lo || (lo_open && v == lo))
    throw SpecError("out_of_range", field(key), "'" + field(key) + "' must be in " + range + ", got " + fmt(v));
  normalized_[key] = v;
  return v;
}

long ObjectReader::integer(const std::string& key, long fallback, long lo, long hi) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  long v = fallback;
  if (const nlohmann::json* j = find(key)) {
    const bool integral =
        j->is_number_integer() ||
        (j->is_number_float() && std::floor(j->get<double>()) == j->get<double>() && std::abs(j->get<double>()) < 1e15);
    if (!integral)
      throw SpecError("wrong_type", field(key),
                      "'" + field(key) + "' must be an integer in " + range + ", got " +
                          (j->is_number() ? j->dump() : type_name(*j)));
    if (j->is_number_unsigned() && j->get<unsigned long>() > static_cast<unsigned long>(hi))
      throw SpecError("out_of_range", field(key), "'" + field(key) + "' must be in " + range + ", got " + j->dump());
    v = j->is_number_integer() ? j->get<long>() : long(j->get<double>());
  }
  if (v < lo || v > hi)
    throw SpecError("out_of_range", field(key),
                    "'" + field(key) + "' must be in " + range + ", got " + std::to_string(v));
  normalized_[key] = v;
  return v;
}

std::string ObjectReader::choice(const std::string& key, const std::string& fallback,
                                 const std::vector<std::string>& allowed) {
  std::string list;
  for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
  std::string v = fallback;
  if (const nlohmann::json* j = find(key)) {
    if (!j->is_string())
      throw SpecError("wrong_type", field(key),
                      "'" + field(key) + "' must be one of: " + list + ", got " + type_name(*j));
    v = j->get<std::string>();
  }
  for (const std::string& a : allowed)
    if (v == a) {
      normalized_[key] = v;
      return v;
    }
  throw SpecError("invalid_value", field(key), "'" + field(key) + "' must be one of: " + list + ", got '" + v + "'");
}

std::string ObjectReader::text(const std::string& key, const std::string& fallback, std::size_t max_length) {
  std::string v = fallback;
  if (const nlohmann::json* j = find(key)) {
    if (!j->is_string())
      throw SpecError("wrong_type", field(key), "'" + field(key) + "' must be a string, got " + type_name(*j));
    v = j->get<std::string>();
  }
  // Characters, not bytes: "é" is one (the parser has already checked the UTF-8; continuation bytes are
  // 10xxxxxx).
  const auto characters =
      std::count_if(v.begin(), v.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; });
  if (std::size_t(characters) > max_length)
    throw SpecError("out_of_range", field(key),
                    "'" + field(key) + "' must be at most " + std::to_string(max_length) + " characters");
  normalized_[key] = v;
  return v;
}

std::vector<double> ObjectReader::numbers(const std::string& key, const std::vector<double>& fallback, double lo,
                                          double hi, std::size_t max_items) {
  std::vector<double> v = fallback;
  if (const nlohmann::json* j = find(key)) {
    if (!j->is_array()) throw SpecError("wrong_type", field(key), "'" + field(key) + "' must be an array of numbers");
    if (j->size() > max_items)
      throw SpecError("out_of_range", field(key),
                      "'" + field(key) + "' may hold at most " + std::to_string(max_items) + " values");
    v.clear();
    for (const auto& e : *j) {
      if (!e.is_number()) throw SpecError("wrong_type", field(key), "'" + field(key) + "' must hold only numbers");
      v.push_back(e.get<double>());
    }
  }
  for (double x : v)
    if (!std::isfinite(x) || x < lo || x > hi)
      throw SpecError("out_of_range", field(key),
                      "'" + field(key) + "' values must be in [" + fmt(lo) + ", " + fmt(hi) + "], got " + fmt(x));
  // A list of whole numbers (a lattice direction, Miller indices) is written as integers: [2, -1, -1], as a user
  // writes it, not [2.0, -1.0, -1.0]; any other list as its numbers. Reading either back gives the same values.
  const bool whole = std::all_of(v.begin(), v.end(), [](double x) { return x == std::trunc(x) && std::abs(x) < 9e15; });
  nlohmann::json out = nlohmann::json::array();
  for (double x : v) out.push_back(whole ? nlohmann::json(std::int64_t(x)) : nlohmann::json(x));
  normalized_[key] = out;
  return v;
}

std::vector<long> ObjectReader::integers(const std::string& key, long lo, long hi, std::size_t max_items) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  std::vector<long> v;
  if (const nlohmann::json* j = find(key)) {
    if (!j->is_array()) throw SpecError("wrong_type", field(key), "'" + field(key) + "' must be an array of integers");
    if (j->size() > max_items)
      throw SpecError("out_of_range", field(key),
                      "'" + field(key) + "' may hold at most " + std::to_string(max_items) + " values");
    for (const auto& e : *j) {
      if (!e.is_number_integer())
        throw SpecError("wrong_type", field(key),
                        "'" + field(key) + "' must hold only integers in " + range + ", got " + e.dump());
      const long x = e.get<long>();
      if (x < lo || x > hi || (e.is_number_unsigned() && e.get<unsigned long>() > (unsigned long)hi))
        throw SpecError("out_of_range", field(key),
                        "'" + field(key) + "' values must be in " + range + ", got " + e.dump());
      v.push_back(x);
    }
  }
  normalized_[key] = v;
  return v;
}

std::vector<nlohmann::json> ObjectReader::objects(const std::string& key, std::size_t max_items) {
  std::vector<nlohmann::json> v;
  if (const nlohmann::json* j = find(key)) {
    if (!j->is_array()) throw SpecError("wrong_type", field(key), "'" + field(key) + "' must be an array of objects");
    if (j->size() > max_items)
      throw SpecError("out_of_range", field(key),
                      "'" + field(key) + "' may hold at most " + std::to_string(max_items) + " entries");
    for (const auto& e : *j) v.push_back(e);
  }
  normalized_[key] = nlohmann::json::array();
  return v;
}

nlohmann::json ObjectReader::finish() {
  for (auto it = object_.begin(); it != object_.end(); ++it)
    if (!seen_.count(it.key()))
      throw SpecError("unknown_field", field(it.key()), "unknown field '" + field(it.key()) + "'");
  return normalized_;
}

}  // namespace granulab::api
