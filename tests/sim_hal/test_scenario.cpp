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
       "s.json:5: \"kind\" must be \"round\", \"iss\", \"iss_mesh\" or \"module_rail\", not "
       "\"square\""},
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
  // Rack walls and meshes: each mistake named with its line and key.
  const std::string head = "{\n \"name\": \"t\",\n \"scene\": {\"rack_walls\": [{\n";
  const std::string wall = "  \"center\": [0, 0, 0], \"normal\": [1, 0, 0],\n";
  const std::string tail = "}]},\n \"poses\": [{\"position\": [1, 0, 0]}]\n}";
  const std::string face = "  \"faces\": [{\"u\": [-1, 1], \"v\": [-1, 1], \"depth\": 0}]";
  const Case rack_cases[] = {
      {head + wall + "  \"colour\": 1,\n" + face + tail,
       "s.json:5: unknown key \"colour\" in a rack wall"},
      {head + wall + "  \"faces\": []" + tail,
       "s.json:5: \"faces\" must hold at least one rack face"},
      {head + wall + "  \"faces\": [\n   {\"u\": [1, -1], \"v\": [-1, 1]}]" + tail,
       "s.json:6: \"u\" = [1, -1] must rise within -20 .. 20"},
      {head + wall + "  \"faces\": [\n   {\"u\": [-1, 1], \"v\": [-1, 1], \"depth\": 2}]" + tail,
       "s.json:6: \"depth\" = 2 is outside -1 .. 0.5"},
      {head + wall + "  \"faces\": [\n   {\"u\": [-1, 1], \"v\": [-1, 1], \"depht\": 0}]" + tail,
       "s.json:6: unknown key \"depht\" in a rack face"},
      {head + wall + face + ",\n  \"seat_tracks\": [\n   {\"from\": [2, 0], \"to\": [3, 0]}]" +
           tail,
       "s.json:7: no rack face under the seat track's centre: give its \"depth\""},
      {head + wall + face + ",\n  \"seat_tracks\": [\n   {\"from\": [0, 0], \"to\": [0.01, 0]}]" +
           tail,
       "s.json:7: a seat track must be at least 5 cm long"},
      {head + wall + face + ",\n  \"seat_tracks\": [\n   {\"from\": [0, 0, 0], \"to\": [1, 0]}]" +
           tail,
       "s.json:7: \"from\" must be [u_m, v_m]"},
      {head + wall + face + ",\n  \"gaps\": [\n   {\"u\": [0, 1], \"v\": [0, 1], \"rim\": 0}]" +
           tail,
       "s.json:7: unknown key \"rim\" in a gap"},
      {head + wall + face + ",\n  \"bays\": [\n   {\"u\": [0, 1], \"v\": [0, 1], \"depth\": 0.1}]" +
           tail,
       "s.json:7: \"depth\" = 0.1 is outside -1.5 .. -0.01"},
      {head + wall + face +
           ",\n  \"strips\": [\n   {\"u\": [0, 1], \"v\": [0, 1], \"height\": 0.5}]" + tail,
       "s.json:7: \"height\" = 0.5 is outside 0.001 .. 0.05"},
      {head + "  \"center\": [0, 0, 0], \"normal\": [1, 0, 0], \"up\": [1, 0, 0],\n" + face + tail,
       "s.json:3: \"up\" must not be parallel to \"normal\""},
      {"{\n \"name\": \"t\",\n \"scene\": {\"meshes\": [\n  {\"path\": \"/nonexistent.dae\"}]},\n"
       " \"poses\": [{\"position\": [1, 0, 0]}]\n}",
       "s.json:4: /nonexistent.dae: cannot load mesh: Unable to open file \"/nonexistent.dae\"."},
      {"{\n \"name\": \"t\",\n \"scene\": {\"meshes\": [\n  {\"path\": \"x.dae\", \"scale\": "
       "2}]},\n"
       " \"poses\": [{\"position\": [1, 0, 0]}]\n}",
       "s.json:4: unknown key \"scale\" in a mesh"},
  };
  for (const Case& c : rack_cases) {
    sim_hal::Scenario s;
    std::string error;
    assert_false(sim_hal::parse_scenario(c.text, "s.json", &s, &error));
    if (error != c.error) print_error("got: %s\nwant: %s\n", error.c_str(), c.error);
    assert_string_equal(error.c_str(), c.error);
  }
  // The same wall without mistakes loads: no plain wall needed.
  {
    sim_hal::Scenario s;
    std::string error;
    assert_true(sim_hal::parse_scenario(head + wall + face + tail, "s.json", &s, &error));
    assert_int_equal(s.scene.rack_walls.size(), 1);
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
