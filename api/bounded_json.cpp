#include "api/bounded_json.h"

#include <vector>

#include "api/spec_error.h"

namespace granulab::api {

namespace {

using nlohmann::json;

class BoundedBuilder : public nlohmann::json_sax<json> {
 public:
  explicit BoundedBuilder(std::size_t max_depth) : max_depth_(max_depth) {}

  bool null() override { return add(nullptr); }
  bool boolean(bool v) override { return add(v); }
  bool number_integer(number_integer_t v) override { return add(v); }
  bool number_unsigned(number_unsigned_t v) override { return add(v); }
  bool number_float(number_float_t v, const string_t&) override { return add(v); }
  bool string(string_t& v) override { return add(std::move(v)); }
  bool binary(binary_t& v) override { return add(json::binary(std::move(v))); }
  bool start_object(std::size_t) override { return open(json::object()); }
  bool key(string_t& k) override {
    path_.back().key = k;
    // A key given twice: which one counts would be a guess (nlohmann keeps the last, others the first).
    if (path_.back().node->contains(k)) {
      error_ = SpecError("duplicate_field", field(), "'" + field() + "' is given twice");
      return false;
    }
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(json::array()); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    if (e.id == 406) {  // a number the lexer read but a double cannot hold
      error_ = SpecError("out_of_range", field(), "'" + field() + "' is a number too large for a double");
    } else {
      // The message may quote the offending bytes: keep it valid UTF-8 for the JSON error answer.
      error_ = SpecError("invalid_json", "",
                         std::string("the spec is not valid JSON: ") +
                             json(e.what()).dump(-1, ' ', false, json::error_handler_t::replace));
    }
    return false;
  }

  json take() { return std::move(root_); }
  const SpecError& error() const { return error_; }

 private:
  struct Level {
    json* node;
    std::string key;  // the current key of an object
  };

  json* place(json value) {
    if (path_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    json& parent = *path_.back().node;
    if (parent.is_array()) {
      parent.push_back(std::move(value));
      return &parent.back();
    }
    json& slot = parent[path_.back().key];
    slot = std::move(value);
    return &slot;
  }
  bool add(json value) {
    place(std::move(value));
    return true;
  }
  bool open(json container) {
    if (path_.size() >= max_depth_) {
      error_ = SpecError("too_deep", field(),
                         "the spec nests objects and arrays deeper than " + std::to_string(max_depth_) +
                             " levels (at '" + field() + "')");
      return false;
    }
    json* node = place(std::move(container));
    path_.push_back({node, ""});
    return true;
  }
  bool close() {
    path_.pop_back();
    return true;
  }
  // The dotted path of the value being read: keys, and [i] for array elements.
  std::string field() const {
    std::string out;
    for (std::size_t k = 0; k < path_.size(); ++k) {
      const Level& l = path_[k];
      // An open level's child is its last element; at the innermost level, the element being read is next.
      const bool innermost = k + 1 == path_.size();
      if (l.node->is_array()) out += "[" + std::to_string(l.node->size() - (innermost ? 0 : 1)) + "]";
      else if (!l.key.empty()) out += (out.empty() ? "" : ".") + l.key;
    }
    return out;
  }

  std::size_t max_depth_;
  json root_;
  std::vector<Level> path_;
  SpecError error_{"invalid_json", "", "the spec is not valid JSON"};
};

}  // namespace

nlohmann::json parse_bounded_json(const std::string& text, std::size_t max_depth) {
  // nlohmann's lexer takes a NUL byte for the end of the input: `{...}\0garbage` would pass. JSON has no
  // raw NUL anywhere (inside strings it must be escaped), so one is invalid wherever it is.
  if (const auto nul = text.find('\0'); nul != std::string::npos)
    throw SpecError("invalid_json", "", "the spec is not valid JSON: a NUL byte at offset " + std::to_string(nul));
  BoundedBuilder builder(max_depth);
  if (!json::sax_parse(text, &builder)) throw builder.error();
  return builder.take();
}

}  // namespace granulab::api
