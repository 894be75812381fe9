#include <string>

#include "cmocka_cpp.hpp"
#include "hal/json.hpp"

using hal::JsonValue;

namespace {

void test_parses_values_with_lines(void**) {
  JsonValue v;
  std::string error;
  const char* text =
      "{\n \"a\": 1.5,\n \"b\": [true, null, \"x\\ny\"],\n \"c\": {\"d\": -2e3}\n}\n";
  assert_true(hal::parse_json(text, &v, &error));
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

void test_errors_name_the_line(void**) {
  struct Case {
    const char* text;
    const char* error;
  } cases[] = {
      {"{\n \"a\": 1,\n \"b\": }", "line 3: unexpected character '}'"},
      {"{\"a\": 1, \"a\": 2}", "line 1: duplicate key \"a\""},
      {"[1, 2", "line 1: unterminated array"},
      {"{\"a\" 1}", "line 1: expected ':' after key \"a\""},
      {"\"abc", "line 1: unterminated string"},
      {"{}\n\nx", "line 3: unexpected text after the document"},
      {"", "line 1: unexpected end of file, expected a value"},
  };
  for (const Case& c : cases) {
    JsonValue v;
    std::string error;
    assert_false(hal::parse_json(c.text, &v, &error));
    assert_string_equal(error.c_str(), c.error);
  }
  // Deep nesting is refused, not a stack overflow.
  std::string deep(100, '[');
  JsonValue v;
  std::string error;
  assert_false(hal::parse_json(deep, &v, &error));
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_parses_values_with_lines),
      cmocka_unit_test(test_errors_name_the_line),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
