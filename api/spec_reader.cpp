#include "api/spec_reader.h"

namespace granulab::api {

SpecReader::SpecReader(const nlohmann::json& document) : document_(document), top_(document) {}

void SpecReader::section(const char* name) {
  section_ = name;
  if (section_.empty() || sections_.count(section_)) return;
  top_.known(section_);
  sections_[section_] = std::make_unique<ObjectReader>(document_, section_, section_);
}

ObjectReader& SpecReader::current() {
  if (item_) return *item_;
  return section_.empty() ? top_ : *sections_.at(section_);
}

void SpecReader::number(const char* key, double& value, Range range, const char*, const char*) {
  value = current().number(key, value, range.lo, range.hi, range.lo_open);
}

void SpecReader::integer(const char* key, int& value, long lo, long hi, const char*) {
  value = int(current().integer(key, value, lo, hi));
}

void SpecReader::choice(const char* key, std::string& value, const std::vector<std::string>& allowed, const char*) {
  value = current().choice(key, value, allowed);
}

void SpecReader::text(const char* key, std::string& value, std::size_t max_length, const char*) {
  value = current().text(key, value, max_length);
}

void SpecReader::numbers(const char* key, std::vector<double>& values, Range range, std::size_t max_items, const char*,
                         const char*) {
  values = current().numbers(key, values, range.lo, range.hi, max_items);
}

void SpecReader::grain_ids(const char* key, std::vector<GrainId>& values, std::uint32_t last, const char*,
                           std::size_t max_items, const char*) {
  values.clear();
  for (long id : current().integers(key, 0, long(last), max_items)) values.push_back(GrainId(std::uint32_t(id)));
}

std::size_t SpecReader::begin_list(const char* key, std::size_t max_items, const char*) {
  list_key_ = key;
  list_items_ = current().objects(key, max_items);
  list_normalized_ = nlohmann::json::array();
  return list_items_.size();
}

void SpecReader::begin_item(std::size_t index) {
  const std::string path = current().field(list_key_) + "[" + std::to_string(index) + "]";
  const nlohmann::json holder = {{"item", list_items_.at(index)}};
  item_ = std::make_unique<ObjectReader>(holder, "item", path);
}

void SpecReader::end_item() {
  list_normalized_.push_back(item_->finish());
  item_.reset();
}

void SpecReader::end_list() {
  current().set_normalized(list_key_, list_normalized_);
  list_key_.clear();
  list_items_.clear();
}

bool SpecReader::present(const char* key) { return current().has(key); }

void SpecReader::require(bool ok, const char* field, const std::string& message) {
  if (!ok) throw SpecError("out_of_range", field, message);
}

nlohmann::json SpecReader::finish() {
  nlohmann::json out = top_.finish();
  for (auto& [name, reader] : sections_) out[name] = reader->finish();
  return out;
}

}  // namespace granulab::api
