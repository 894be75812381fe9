#include <cstring>
#include <string>

#include "cmocka_cpp.hpp"
#include "formats/json.hpp"

using formats::JsonValue;

namespace {

void test_parses_values_with_lines(void**) {
  JsonValue v;
  std::string error;
  const char* text =
      "{\n \"a\": 1.5,\n \"b\": [true, null, \"x\\ny\"],\n \"c\": {\"d\": -2e3}\n}\n";
  assert_true(formats::parse_json(text, &v, &error));
  assert_true(v.is_object());
  assert_near(v.find("a")->number, 1.5, 0);
  assert_int_equal(v.find("a")->line, 2);
  const JsonValue* b = v.find("b");
  assert_int_equal(b->items.size(), 3);
  assert_true(b->items[0].boolean);
  assert_int_equal(static_cast<int>(b->items[1].type), static_cast<int>(JsonValue::Type::kNull));
  assert_string_equal(b->items[2].text.c_str(), "x\ny");
  assert_near(v.find("c")->find("d")->number, -2000.0, 0);
  assert_int_equal(v.find("c")->line, 4);
  assert_null(v.find("missing"));
}

// Errors say the line and what was wrong; the words after "line N: " are
// nlohmann-json's own for syntax errors, ours for what it lets through.
void test_errors_name_the_line(void**) {
  struct Case {
    const char* text;
    const char* starts;    // the error begins with this
    const char* mentions;  // and contains this
  } cases[] = {
      {"{\n \"a\": 1,\n \"b\": }", "line 3: ", "unexpected '}'"},
      {"{\"a\": 1, \"a\": 2}", "line 1: ", "duplicate key \"a\""},
      {"{\n\"a\": 1,\n\n\"a\": 2}", "line 4: ", "duplicate key \"a\""},
      {"[1, 2", "line 1: ", "unexpected end of input"},
      {"{\"a\" 1}", "line 1: ", "expected ':'"},
      {"\"abc", "line 1: ", "missing closing quote"},
      {"{}\n\nx", "line 3: ", "expected end of input"},
      {"", "line 1: ", "unexpected end of input"},
      {"{\"a\": 0x14}", "line 1: ", "syntax error"},
      {"{\"a\": 1,}", "line 1: ", "expected string literal"},
      {"{\"a\": \"x\ny\"}", "line 1: ", "control character"},
  };
  for (const Case& c : cases) {
    JsonValue v;
    std::string error;
    assert_false(formats::parse_json(c.text, &v, &error));
    if (error.rfind(c.starts, 0) != 0 || error.find(c.mentions) == std::string::npos) {
      fail_msg("\"%s\": got \"%s\", expected \"%s...%s\"", c.text, error.c_str(), c.starts,
               c.mentions);
    }
    // Nothing half-parsed is left behind.
    assert_true(v.type == JsonValue::Type::kNull);
  }
}

// Lines are right for values after numbers at line ends, in arrays, and for
// nested objects.
void test_lines_of_every_kind_of_value(void**) {
  const char* text = "[1,\n2\n,\n{\"k\":\n true},\n\"s\"]";
  JsonValue v;
  std::string error;
  assert_true(formats::parse_json(text, &v, &error));
  assert_int_equal(v.items.size(), 4);
  assert_int_equal(v.items[0].line, 1);
  assert_int_equal(v.items[1].line, 2);
  assert_int_equal(v.items[2].line, 4);
  assert_int_equal(v.items[2].find("k")->line, 5);
  assert_int_equal(v.items[3].line, 6);
}

// Hostile input is refused or parsed in bounded time and memory: 10,000
// levels of nesting are refused at the limit (no stack overflow), 80,000
// keys parse (the old duplicate check was quadratic and took 14 s), and a
// document of more than kMaxJsonValues values is refused at the limit
// rather than building a tree of gigabytes (the speed is measured in
// formats_bench, not here).
void test_hostile_documents_are_bounded(void**) {
  JsonValue v;
  std::string error;
  const std::string deep(10000, '[');
  assert_false(formats::parse_json(deep, &v, &error));
  assert_non_null(std::strstr(error.c_str(), "nesting deeper than 64 levels"));

  std::string many = "{";
  for (int k = 0; k < 80000; ++k) {
    if (k) many += ",\n";
    many += "\"key" + std::to_string(k) + "\": " + std::to_string(k);
  }
  many += "}";
  assert_true(formats::parse_json(many, &v, &error));
  assert_int_equal(v.members.size(), 80000);
  assert_int_equal(v.members[79999].second.line, 80000);
  assert_true(v.members[79999].second.number == 79999.0);

  std::string repeated = many.substr(0, many.size() - 1) + ",\n\"key40000\": 1}";
  assert_false(formats::parse_json(repeated, &v, &error));
  assert_string_equal(error.c_str(), "line 80001: duplicate key \"key40000\"");

  // The array counts as one value: kMaxJsonValues - 1 items reach the limit.
  const auto array_of = [](std::size_t items) {
    std::string text = "[0";
    for (std::size_t k = 1; k < items; ++k) text += ",7";
    return text + "]";
  };
  assert_true(formats::parse_json(array_of(formats::kMaxJsonValues - 1), &v, &error));
  assert_int_equal(v.items.size(), formats::kMaxJsonValues - 1);
  assert_false(formats::parse_json(array_of(formats::kMaxJsonValues), &v, &error));
  assert_string_equal(error.c_str(), "line 1: more than 1048576 values");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_parses_values_with_lines),
      cmocka_unit_test(test_errors_name_the_line),
      cmocka_unit_test(test_lines_of_every_kind_of_value),
      cmocka_unit_test(test_hostile_documents_are_bounded),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
