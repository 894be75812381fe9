#include <string>

#include "cmocka_cpp.hpp"
#include "detection_json.hpp"
#include "formats/detector_config_io.hpp"
#include "png_image.hpp"

namespace {

void test_config_file(void**) {
  estimator::DetectorConfig cfg;
  std::string error;
  assert_true(
      formats::parse_detector_config("{\n \"handrail\": {\"kind\": \"round\", \"bar_length_m\": "
                                     "1.055},\n \"line_iterations\": 120,\n"
                                     " \"gripper_angle_deg\": 90\n}",
                                     "c.json", &cfg, &error));
  assert_near(cfg.handrail.bar_length_m, 1.055, 1e-6);
  assert_near(cfg.handrail.bar_width_m, 0.035, 1e-6);
  assert_int_equal(cfg.line_iterations, 120);
  assert_near(cfg.gripper_angle_rad, M_PI / 2, 1e-6);

  struct Case {
    const char* text;
    const char* error;
  } cases[] = {
      {"{\n \"line_iterations\": 0\n}",
       "c.json:2: \"line_iterations\" is out of range or inconsistent with the other settings"},
      {"{\n \"speed\": 3\n}", "c.json:2: unknown key \"speed\""},
      {"{\n \"plane_inlier_m\": \"big\"\n}", "c.json:2: \"plane_inlier_m\" must be a number"},
      {"{\n \"handrail\": {\"kind\": \"oval\"}\n}",
       "c.json:2: \"handrail.kind\" must be \"iss\" or \"round\""},
      {"{\n \"min_line_inliers\": 2.5\n}",
       "c.json:2: \"min_line_inliers\" must be a non-negative integer"},
      {"{\n\n",
       "c.json:3: syntax error while parsing object key - unexpected end of input; expected "
       "string literal"},
  };
  for (const Case& c : cases) {
    estimator::DetectorConfig before;
    assert_false(formats::parse_detector_config(c.text, "c.json", &before, &error));
    if (error != c.error) print_error("got: %s\nwant: %s\n", error.c_str(), c.error);
    assert_string_equal(error.c_str(), c.error);
  }
}

void test_detection_json(void**) {
  estimator::HandrailDetection d;
  d.status = estimator::DetectStatus::kNoLine;
  d.processing_time_us = 1250;
  assert_string_equal(tools::detection_to_json("a\"b.pcd", d).c_str(),
                      "{\"frame\":\"a\\\"b.pcd\",\"state\":\"NH\",\"reason\":\"NO_LINE\",\"first_"
                      "line\":\"ACCEPTED\",\"time_ms\":1.250}");
  d.status = estimator::DetectStatus::kFound;
  d.state = estimator::HandrailState::kOneEnd;
  d.end_seen[1] = true;
  d.ends_cam[1] = Eigen::Vector3f(1, 2, 3);
  d.R_cam_handrail = d.R_cam_target = Eigen::Matrix3f::Identity();
  const std::string s = tools::detection_to_json("f.pcd", d);
  assert_true(s.find("\"state\":\"OE\"") != std::string::npos);
  assert_true(s.find("\"ends\":[[1.00000,2.00000,3.00000]]") != std::string::npos);
  assert_true(s.find("\"target_rotation\":[[1.00000,0.00000,0.00000],") != std::string::npos);
}

void test_image_text_and_png(void**) {
  tools::Image img(40, 12);
  img.text(1, 1, "OK 1", {255, 255, 255});
  int lit = 0;
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 40; ++x) lit += img.get(x, y).r > 0;
  assert_true(lit > 20);
  std::string error;
  assert_false(img.write_png("/nonexistent/dir/x.png", &error));
  assert_string_equal(error.c_str(), "/nonexistent/dir/x.png: cannot create the PNG file");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_config_file),
      cmocka_unit_test(test_detection_json),
      cmocka_unit_test(test_image_text_and_png),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
