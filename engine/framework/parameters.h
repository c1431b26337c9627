// An experiment's parameters, stated once: each experiment walks its parameter struct through a
// ParameterVisitor, naming every field with its default (the value it holds), its allowed range, its
// unit and its meaning. The api's spec reader is a visitor that fills the fields from JSON (and rejects
// what the ranges forbid, naming the field); the API schema and the docs' spec tables are visitors that
// write the same fields out. So a field added here is read, validated, normalised and documented at once.
//
// Fields belong to the section named by the last section() call ("" = the top level of the spec).
// Defaults that depend on other fields (e.g. the platens' friction defaults to the grains') are set on
// the struct before the field is visited; rules between fields are require() calls.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "engine/core/types.h"

namespace granulab {

/// Allowed values of a number: [lo, hi], or (lo, hi] when lo_open. `hi_is` names what hi is when it
/// depends on another field (e.g. "loading.max_strain"): the docs state it in words, not as a number.
struct Range {
  double lo, hi;
  bool lo_open = false;
  const char* hi_is = nullptr;
};

class ParameterVisitor {
 public:
  virtual ~ParameterVisitor() = default;

  /// The next fields belong to this section of the spec ("grain", "loading", ...; "" = top level).
  virtual void section(const char* name) = 0;
  virtual void number(const char* key, double& value, Range range, const char* unit, const char* meaning) = 0;
  virtual void integer(const char* key, int& value, long lo, long hi, const char* meaning) = 0;
  /// One of `allowed` (a name).
  virtual void choice(const char* key, std::string& value, const std::vector<std::string>& allowed,
                      const char* meaning) = 0;
  /// Free text of at most max_length characters.
  virtual void text(const char* key, std::string& value, std::size_t max_length, const char* meaning) = 0;
  /// A list of numbers each in `range`, at most max_items.
  virtual void numbers(const char* key, std::vector<double>& values, Range range, std::size_t max_items,
                       const char* unit, const char* meaning) = 0;
  /// A list of grain ids each in [0, last], at most max_items; `last_is` says in words what last is (it
  /// depends on other fields).
  virtual void grain_ids(const char* key, std::vector<GrainId>& values, std::uint32_t last, const char* last_is,
                         std::size_t max_items, const char* meaning) = 0;
  /// A list of objects: returns how many items to visit (a reader: how many the spec holds; a writer
  /// describing the schema: one). Visit item i's fields between begin_item(i) and end_item(), then
  /// call end_list().
  virtual std::size_t begin_list(const char* key, std::size_t max_items, const char* meaning) = 0;
  virtual void begin_item(std::size_t index) = 0;
  virtual void end_item() = 0;
  virtual void end_list() = 0;
  /// Whether the object being read holds `key`: for list items made of one of several alternatives
  /// (a loading program's segment). Visitors that describe the spec answer true, describing them all.
  virtual bool present(const char* key) {
    (void)key;
    return true;
  }
  /// A rule between fields: when `ok` is false the spec is rejected, naming `field` (dotted path).
  virtual void require(bool ok, const char* field, const std::string& message) = 0;
};

}  // namespace granulab
