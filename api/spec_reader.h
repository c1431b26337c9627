// Reads a spec's JSON into an experiment's parameters: the ParameterVisitor that fills each visited
// field from its section of the document (ObjectReader: types, ranges, errors that name the field),
// and collects the normalised spec with every default filled in.
#pragma once

#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "api/object_reader.h"
#include "engine/framework/parameters.h"

namespace granulab::api {

class SpecReader : public ParameterVisitor {
 public:
  explicit SpecReader(const nlohmann::json& document);

  void section(const char* name) override;
  void number(const char* key, double& value, Range range, const char* unit, const char* meaning) override;
  void integer(const char* key, int& value, long lo, long hi, const char* meaning) override;
  void choice(const char* key, std::string& value, const std::vector<std::string>& allowed,
              const char* meaning) override;
  void text(const char* key, std::string& value, std::size_t max_length, const char* meaning) override;
  void numbers(const char* key, std::vector<double>& values, Range range, std::size_t max_items, const char* unit,
               const char* meaning) override;
  void grain_ids(const char* key, std::vector<GrainId>& values, std::uint32_t last, const char* last_is,
                 std::size_t max_items, const char* meaning) override;
  std::size_t begin_list(const char* key, std::size_t max_items, const char* meaning) override;
  void begin_item(std::size_t index) override;
  void end_item() override;
  void end_list() override;
  bool present(const char* key) override;
  void require(bool ok, const char* field, const std::string& message) override;

  /// Throws SpecError on keys no one visited (top level first); returns the normalised spec.
  nlohmann::json finish();

 private:
  ObjectReader& current();

  const nlohmann::json& document_;
  ObjectReader top_;
  std::map<std::string, std::unique_ptr<ObjectReader>> sections_;
  std::string section_;  // "" = top level
  // The list being read, if any: its elements, the reader of the current one, the normalised items.
  std::string list_key_;
  std::vector<nlohmann::json> list_items_;
  std::unique_ptr<ObjectReader> item_;
  nlohmann::json list_normalized_;
};

}  // namespace granulab::api
