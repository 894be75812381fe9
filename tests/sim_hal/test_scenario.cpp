#include <dirent.h>

#include <string>

#include "cmocka_cpp.hpp"
#include "sim_hal/scenario.hpp"
#include "test_data.hpp"

namespace {

const char* kMinimal = R"({
  "name": "t",
  "scene": {"walls": [{"center": [0, 0, 0], "normal": [1, 0, 0], "size": [2, 2]}]},
  "poses": [{"position": [0.6, 0, 0], "frames": 3, "to": {"position": [0.3, 0, 0]}}]
})";

void test_minimal_scenario(void**) {
  sim_hal::Scenario s;
  std::string error;
  assert_true(sim_hal::parse_scenario(kMinimal, "t.json", &s, &error));
  assert_int_equal(s.T_world_cam.size(), 3);
  assert_near(s.T_world_cam[1].translation().x(), 0.45, 1e-12);
  // The camera looks along world -x by default: its z axis.
  assert_near(s.T_world_cam[0].rotation().col(2).x(), -1.0, 1e-12);
}

void test_errors_name_file_and_line(void**) {
  struct Case {
    std::string text;
    const char* error;
  } cases[] = {
      {"{\n \"name\": \"t\",\n \"scene\": {\"walls\": []},\n \"poses\": []\n}",
       "s.json:3: \"walls\" must hold at least one wall"},
      {"{\n \"name\": \"t\",\n \"colour\": 3\n}",
       "s.json:3: unknown key \"colour\" in the scenario"},
      {"{\n \"name\": 5\n}", "s.json:2: \"name\" must be a string, not a number"},
      {"{\n \"name\": \"t\",\n \"scene\": {\"walls\": [{\"center\": [0, 0, 0], \"normal\": [1, 0, "
       "0], \"size\": [2, 2]}],\n"
       "  \"handrails\": [\n   {\"kind\": \"square\", \"foot\": [0,0,0], \"normal\": [1,0,0], "
       "\"axis\": [0,0,1], \"length\": 0.5}]},\n"
       " \"poses\": [{\"position\": [1, 0, 0]}]\n}",
       "s.json:5: \"kind\" must be \"round\", \"iss\" or \"iss_mesh\", not \"square\""},
      {"{\n \"name\": \"t\",\n \"seed\": 1,\n \"scene\": {\n}",
       "s.json:5: syntax error while parsing object - unexpected end of input; expected '}'"},
      {"{\"name\": \"t\", \"scene\": {\"walls\": [{\"center\": [0, 0, 0], \"normal\": [1, 0, 0], "
       "\"size\": [2, 2]}]},\n"
       " \"poses\": [{\"position\": [1, 0, 0], \"frames\": 0}]}",
       "s.json:2: \"frames\" = 0 is outside 1 .. 100000"},
  };
  for (const Case& c : cases) {
    sim_hal::Scenario s;
    std::string error;
    assert_false(sim_hal::parse_scenario(c.text, "s.json", &s, &error));
    if (error != c.error) print_error("got: %s\nwant: %s\n", error.c_str(), c.error);
    assert_string_equal(error.c_str(), c.error);
  }
  sim_hal::Scenario s;
  std::string error;
  assert_false(sim_hal::load_scenario("/nonexistent.json", &s, &error));
  assert_string_equal(error.c_str(), "/nonexistent.json: cannot open (No such file or directory)");
}

void test_shipped_scenarios_load(void**) {
  const char* root = std::getenv("HRP_SOURCE_DIR");
  const std::string dir = std::string(root ? root : ".") + "/sim_hal/scenarios";
  DIR* d = opendir(dir.c_str());
  assert_non_null(d);
  int loaded = 0;
  while (dirent* e = readdir(d)) {
    const std::string name = e->d_name;
    if (name.size() < 6 || name.compare(name.size() - 5, 5, ".json") != 0) continue;
    sim_hal::Scenario s;
    std::string error;
    if (!sim_hal::load_scenario(dir + "/" + name, &s, &error)) print_error("%s\n", error.c_str());
    assert_true(error.empty());
    assert_true(!s.T_world_cam.empty());
    ++loaded;
  }
  closedir(d);
  assert_true(loaded >= 8);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_minimal_scenario),
      cmocka_unit_test(test_errors_name_file_and_line),
      cmocka_unit_test(test_shipped_scenarios_load),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
