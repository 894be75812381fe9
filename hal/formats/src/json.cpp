#include "formats/json.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <unordered_set>

#include "formats/text_file.hpp"

namespace formats {
namespace {

// A character iterator that records how far nlohmann's lexer has read, so
// that the SAX handler can tell the line of each value it is handed.
class TrackedIterator {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  TrackedIterator(const char* p, const char** furthest) : p_(p), furthest_(furthest) {}
  reference operator*() const { return *p_; }
  TrackedIterator& operator++() {
    ++p_;
    if (p_ > *furthest_) *furthest_ = p_;
    return *this;
  }
  TrackedIterator operator++(int) {
    TrackedIterator before = *this;
    ++*this;
    return before;
  }
  bool operator==(const TrackedIterator& o) const { return p_ == o.p_; }
  bool operator!=(const TrackedIterator& o) const { return p_ != o.p_; }

 private:
  const char* p_;
  const char** furthest_;
};

// Builds the JsonValue tree from SAX events. Every open object keeps a hash
// set of its keys, so a duplicate is found in constant time (the old
// parser compared each key with every earlier one).
class TreeBuilder {
 public:
  using json = nlohmann::json;

  TreeBuilder(std::string_view text, JsonValue* root, const char** furthest)
      : begin_(text.data()), end_(text.data() + text.size()), furthest_(furthest), root_(root) {}

  const std::string& message() const { return message_; }
  int message_line() const { return message_line_; }

  bool null() { return scalar(JsonValue::Type::kNull, false); }
  bool boolean(bool b) {
    JsonValue* v = place(false);
    if (!v) return false;
    v->type = JsonValue::Type::kBool;
    v->boolean = b;
    return true;
  }
  bool number_integer(json::number_integer_t n) { return number(static_cast<double>(n)); }
  bool number_unsigned(json::number_unsigned_t n) { return number(static_cast<double>(n)); }
  bool number_float(json::number_float_t n, const std::string&) { return number(n); }
  bool string(std::string& s) {
    JsonValue* v = place(false);
    if (!v) return false;
    v->type = JsonValue::Type::kString;
    v->text = std::move(s);
    return true;
  }
  bool binary(json::binary_t&) { return fail(line_now(false), "binary values are not JSON"); }
  bool start_object(std::size_t) { return open(JsonValue::Type::kObject); }
  bool end_object() { return close(); }
  bool start_array(std::size_t) { return open(JsonValue::Type::kArray); }
  bool end_array() { return close(); }
  bool key(std::string& k) {
    if (!keys_.back().insert(k).second) {
      return fail(line_now(false), "duplicate key \"" + k + "\"");
    }
    pending_key_ = std::move(k);
    return true;
  }
  bool parse_error(std::size_t chars_read, const std::string&,
                   const nlohmann::detail::exception& e) {
    // nlohmann's text reads "[json.exception.parse_error.101] parse error
    // at line 3, column 7: syntax error while parsing ..."; keep the part
    // after the position, the line is reported our way.
    std::string what = e.what();
    const std::size_t colon = what.find(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    // chars_read counts the offending character (or the end of input).
    const std::size_t offset = chars_read > 0 ? chars_read - 1 : 0;
    return fail(line_at(begin_ + std::min(offset, static_cast<std::size_t>(end_ - begin_))), what);
  }

 private:
  bool fail(int line, std::string what) {
    if (message_.empty()) {
      message_ = std::move(what);
      message_line_ = line;
    }
    return false;
  }
  // The line of the character at `at`: newlines before it, counted once
  // as the lexer moves on (`at` may step back by the one character the
  // lexer has looked ahead).
  int line_at(const char* at) {
    for (; counted_ < at; ++counted_) line_ += *counted_ == '\n';
    int line = line_;
    for (const char* c = at; c < counted_; ++c) line -= *c == '\n';
    return line;
  }
  // The line the lexer is on. A number is known to have ended only once
  // the character after it is read: `lookahead` leaves that one out.
  int line_now(bool lookahead) {
    return line_at(*furthest_ - (lookahead && *furthest_ > begin_ ? 1 : 0));
  }
  // Where the next value goes: the root, the end of the open array, or the
  // open object under the key just read.
  JsonValue* place(bool lookahead) {
    const int line = line_now(lookahead);
    if (++values_ > kMaxJsonValues) {
      fail(line, "more than " + std::to_string(kMaxJsonValues) + " values");
      return nullptr;
    }
    JsonValue* v = nullptr;
    if (stack_.empty()) {
      v = root_;
    } else if (stack_.back()->is_array()) {
      v = &stack_.back()->items.emplace_back();
    } else {
      v = &stack_.back()->members.emplace_back(std::move(pending_key_), JsonValue{}).second;
      pending_key_.clear();
    }
    v->line = line;
    return v;
  }
  bool scalar(JsonValue::Type type, bool lookahead) {
    JsonValue* v = place(lookahead);
    if (!v) return false;
    v->type = type;
    return true;
  }
  bool number(double n) {
    JsonValue* v = place(true);
    if (!v) return false;
    v->type = JsonValue::Type::kNumber;
    v->number = n;
    return true;
  }
  bool open(JsonValue::Type type) {
    if (static_cast<int>(stack_.size()) >= kMaxJsonDepth) {
      return fail(line_now(false),
                  "nesting deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    }
    JsonValue* v = place(false);
    if (!v) return false;
    v->type = type;
    stack_.push_back(v);
    keys_.emplace_back();
    return true;
  }
  bool close() {
    stack_.pop_back();
    keys_.pop_back();
    return true;
  }

  const char* begin_;
  const char* end_;
  const char** furthest_;
  const char* counted_ = begin_;
  int line_ = 1;
  JsonValue* root_;
  std::vector<JsonValue*> stack_;
  std::vector<std::unordered_set<std::string>> keys_;
  std::string pending_key_;
  std::size_t values_ = 0;
  std::string message_;
  int message_line_ = 1;
};

}  // namespace

const JsonValue* JsonValue::find(std::string_view key) const {
  for (const auto& m : members) {
    if (m.first == key) return &m.second;
  }
  return nullptr;
}

const char* to_string(JsonValue::Type type) {
  switch (type) {
    case JsonValue::Type::kNull:
      return "null";
    case JsonValue::Type::kBool:
      return "boolean";
    case JsonValue::Type::kNumber:
      return "number";
    case JsonValue::Type::kString:
      return "string";
    case JsonValue::Type::kArray:
      return "array";
    case JsonValue::Type::kObject:
      return "object";
  }
  return "unknown";
}

bool parse_json(std::string_view text, JsonValue* out, std::string* error) {
  *out = JsonValue{};
  const char* furthest = text.data();
  TreeBuilder builder(text, out, &furthest);
  const TrackedIterator first(text.data(), &furthest);
  const TrackedIterator last(text.data() + text.size(), &furthest);
  // Strict: the document must end where the text ends; no comments.
  const bool ok = nlohmann::json::sax_parse(first, last, &builder,
                                            nlohmann::json::input_format_t::json, true, false);
  if (ok) return true;
  *out = JsonValue{};
  *error = "line " + std::to_string(builder.message_line()) + ": " +
           (builder.message().empty() ? std::string("not valid JSON") : builder.message());
  return false;
}

bool load_json_file(const std::string& path, JsonValue* out, std::string* error) {
  std::string text;
  if (read_file_bounded(path, kMaxTextFileBytes, &text, error) != FileStatus::kOk) return false;
  std::string json_error;
  if (!parse_json(text, out, &json_error)) {
    *error = path + ":" + json_error.substr(5);  // "line N: ..." -> "PATH:N: ..."
    return false;
  }
  return true;
}

}  // namespace formats
