// Reads one JSON object of a spec: typed fields with defaults and allowed ranges, and an error for
// every key it was not asked about (a typo must not silently fall back to a default).
#pragma once

#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/spec_error.h"

namespace granulab::api {

class ObjectReader {
 public:
  /// `parent` holds the object under `key` (absent = empty object). `path` prefixes field names.
  ObjectReader(const nlohmann::json& parent, const std::string& key, const std::string& path);
  /// Reads the whole document (path "").
  explicit ObjectReader(const nlohmann::json& document);

  /// A number in [lo, hi] (or (lo, hi] with lo_open), stored into the normalised output.
  double number(const std::string& key, double fallback, double lo, double hi, bool lo_open = false);
  long integer(const std::string& key, long fallback, long lo, long hi);
  std::string choice(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed);
  std::string text(const std::string& key, const std::string& fallback, std::size_t max_length);
  /// An array of numbers each in [lo, hi], at most max_items (normalised as integers when all are whole).
  std::vector<double> numbers(const std::string& key, const std::vector<double>& fallback, double lo, double hi,
                              std::size_t max_items);
  /// An array of integers each in [lo, hi], at most max_items.
  std::vector<long> integers(const std::string& key, long lo, long hi, std::size_t max_items);
  /// The elements of an array of objects (absent = empty), for reading each with its own ObjectReader
  /// (path "key[i]").
  std::vector<nlohmann::json> objects(const std::string& key, std::size_t max_items);
  /// Stores an already normalised value (e.g. an array of objects read element by element).
  void set_normalized(const std::string& key, nlohmann::json value) { normalized_[key] = std::move(value); }
  /// Marks a key as known (it is read elsewhere, e.g. a nested object).
  void known(const std::string& key) { seen_.insert(key); }

  /// Whether the object holds `key`, null (the field's default) included; the key is not marked as read.
  bool has(const std::string& key) const { return object_.contains(key); }

  /// Throws on unknown keys; returns the object with every default filled in.
  nlohmann::json finish();

  std::string field(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

 private:
  const nlohmann::json* find(const std::string& key);
  nlohmann::json object_;
  std::string path_;
  std::set<std::string> seen_;
  nlohmann::json normalized_ = nlohmann::json::object();
};

}  // namespace granulab::api
