// fsw_app's configuration file: the shipped file loads, and every kind of
// mistake stops start-up with the file, the line and the key.
#include <cstdlib>
#include <string>

#include "cmocka_cpp.hpp"
#include "fsw_app/app_config.hpp"

namespace {

std::string source_dir() {
  const char* d = std::getenv("HRP_SOURCE_DIR");
  return d ? d : ".";
}

void test_shipped_configuration_loads(void**) {
  fsw_app::AppConfig c;
  std::string error;
  const bool ok =
      fsw_app::load_app_config(source_dir() + "/fsw_app/config/fsw_app.json", &c, &error);
  if (!ok) print_error("%s\n", error.c_str());
  assert_true(ok);
  assert_string_equal(c.use_case.c_str(), "MODE_9_5FPS_2000");
  assert_near(c.perch.geometry.distal_link_m, 0.14, 1e-12);
  assert_near(c.perch.geometry.stow.tilt_rad, M_PI / 2, 1e-12);
  assert_int_equal(c.perch.timeouts.gripper_open, 90000);
  assert_int_equal(c.ports.servo_baud, 1000000);
  // The default mount looks aft: the camera's z is the body's -x.
  assert_near(c.T_body_cam.linear().col(2).x(), -1.0, 1e-12);
}

void test_camera_serial_is_read(void**) {
  // --hal real looks for this camera; none given: the first one found.
  fsw_app::AppConfig c;
  std::string error;
  assert_true(fsw_app::parse_app_config("{}", "cfg.json", &c, &error));
  assert_true(c.camera_serial.empty());
  assert_true(fsw_app::parse_app_config("{\"camera\": {\"serial\": \"0005-1234-0042\"}}",
                                        "cfg.json", &c, &error));
  assert_string_equal(c.camera_serial.c_str(), "0005-1234-0042");
}

// Parses `text`; expects failure with every fragment in the message.
void expect_error(const char* text, std::initializer_list<const char*> fragments) {
  fsw_app::AppConfig c;
  std::string error;
  assert_false(fsw_app::parse_app_config(text, "cfg.json", &c, &error));
  for (const char* f : fragments) {
    if (error.find(f) == std::string::npos) {
      print_error("\"%s\" not in \"%s\"\n", f, error.c_str());
      fail();
    }
  }
}

void test_mistakes_name_file_line_and_key(void**) {
  expect_error("{\n \"lcm_urll\": \"memq://\"\n}", {"cfg.json:2:", "lcm_urll", "unknown key"});
  expect_error("{\"use_case\": \"MODE_FAST\"}", {"use_case", "not a Pico Flexx use case"});
  expect_error("{\"perch\": {\n\"joint_speed_rad_s\": 9}}",
               {"cfg.json:2:", "perch.joint_speed_rad_s", "within"});
  expect_error("{\"perch\": {\"timeouts_ms\": {\"closing\": \"long\"}}}",
               {"perch.timeouts_ms.closing", "must be a number"});
  expect_error("{\"perch\": {\"timeouts_ms\": {\"stuck\": 5}}}",
               {"perch.timeouts_ms.stuck", "unknown key"});
  expect_error("{\"arm\": {\"stow_deg\": [150, 0]}}", {"arm.stow_deg", "outside the joint limits"});
  expect_error("{\"arm\": {\"tilt_limits_deg\": [10, -10]}}", {"arm.tilt_limits_deg", "below"});
  expect_error("{\"arm\": {\"base_m\": [0, 0]}}", {"arm.base_m", "array of 3"});
  expect_error("{\"servos\": {\"tilt_id\": 2, \"pan_id\": 2}}", {"servos.pan_id", "different"});
  expect_error("{\"ports\": {\"servo_baud\": 1.5e7}}", {"ports.servo_baud"});
  expect_error("{\"camera\": {\"serial\": \"0005-1234-0042-99999\"}}",
               {"camera.serial", "16 characters"});
  expect_error("{\"camera\": {\"serial\": \"\"}}", {"camera.serial", "non-empty"});
  expect_error("{\"perch\": {\"max_grasp_attempts\": 2.5}}", {"perch.max_grasp_attempts", "whole"});
  expect_error("{\"estimator\": {\"plane_iterations\": -1}}", {"cfg.json:1:", "plane_iterations"});
  // Found from outside: a hexadecimal number was read as 20, an impossible
  // gripper angle was taken, and estimator keys were named without their
  // section and at the section's line.
  expect_error("{\"arm_rate_hz\": 0x14}", {"cfg.json:1:", "syntax error"});
  expect_error("{\"estimator\": {\n\"seed\": 1,\n\"gripper_angle_deg\": -1000}}",
               {"cfg.json:3:", "\"estimator.gripper_angle_deg\" must be a number within 0 .. 90"});
  expect_error("{\"estimator\": {\n\n\"plane_iterationz\": 5}}",
               {"cfg.json:3:", "unknown key \"estimator.plane_iterationz\""});
  expect_error("{\"estimator\": {\"handrail\": {\"kind\": \"oval\"}}}",
               {"\"estimator.handrail.kind\" must be"});
  expect_error("{\"estimator\": {\"budget_us\": 2.5}}", {"\"estimator.budget_us\"", "whole"});
  const std::string hundred_digits = "{\"arm_rate_hz\": 1" + std::string(100, '0') + "}";
  expect_error(hundred_digits.c_str(), {"cfg.json:1:", "arm_rate_hz", "within"});
  expect_error("{\"camera\": 3}", {"camera", "must be an object"});
  expect_error("[1, 2]", {"must be a JSON object"});
  expect_error("{\"lcm_url\": ", {"cfg.json:"});
  fsw_app::AppConfig c;
  std::string error;
  assert_false(fsw_app::load_app_config("/nonexistent/fsw.json", &c, &error));
  assert_non_null(std::strstr(error.c_str(), "/nonexistent/fsw.json: cannot open"));
}

// The manager's bounds on the pose it flies on: read in their units,
// refused outside their ranges.
void test_pose_bounds_are_read(void**) {
  fsw_app::AppConfig c;
  std::string error;
  assert_true(fsw_app::parse_app_config(
      "{\"approach\": {\"pose_max_position_sigma_m\": 0.1, \"pose_max_attitude_sigma_deg\": 5}}",
      "cfg.json", &c, &error));
  assert_near(c.approach.pose_max_position_sigma_m, 0.1, 1e-12);
  assert_near(c.approach.pose_max_attitude_sigma_rad, 5.0 * M_PI / 180.0, 1e-9);
  expect_error("{\"approach\": {\"pose_max_position_sigma_m\": 0}}",
               {"approach.pose_max_position_sigma_m", "within"});
  expect_error("{\"approach\": {\"pose_max_attitude_sigma_deg\": -3}}",
               {"approach.pose_max_attitude_sigma_deg", "within"});
}

void test_a_failed_load_changes_nothing(void**) {
  fsw_app::AppConfig c;
  c.arm_rate_hz = 33.0;
  std::string error;
  assert_false(fsw_app::parse_app_config("{\"arm_rate_hz\": 50, \"bogus\": 1}", "x", &c, &error));
  assert_near(c.arm_rate_hz, 33.0, 0.0);
  assert_true(fsw_app::parse_app_config("{\"arm_rate_hz\": 50}", "x", &c, &error));
  assert_near(c.arm_rate_hz, 50.0, 0.0);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_shipped_configuration_loads),
      cmocka_unit_test(test_camera_serial_is_read),
      cmocka_unit_test(test_mistakes_name_file_line_and_key),
      cmocka_unit_test(test_pose_bounds_are_read),
      cmocka_unit_test(test_a_failed_load_changes_nothing),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
