#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "cli_number.hpp"
#include "cmocka_cpp.hpp"
#include "detection_json.hpp"
#include "estimator/config_io.hpp"
#include "output_dir.hpp"
#include "png_image.hpp"

namespace {

void test_config_file(void**) {
  estimator::DetectorConfig cfg;
  std::string error;
  assert_true(
      estimator::parse_detector_config("{\n \"handrail\": {\"kind\": \"round\", \"bar_length_m\": "
                                       "1.055},\n \"line_iterations\": 120,\n"
                                       " \"gripper_angle_deg\": 90\n}",
                                       "c.json", &cfg, &error));
  assert_near(cfg.handrail.bar_length_m, 1.055, 1e-6);
  assert_near(cfg.handrail.bar_width_m, 0.035, 1e-6);
  assert_int_equal(cfg.line_iterations, 120);
  assert_near(cfg.gripper_angle_rad, M_PI / 2, 1e-6);
  assert_int_equal(cfg.handrail_type_count, 5);  // every ISS length unless told

  estimator::DetectorConfig two;
  assert_true(estimator::parse_detector_config(
      "{\"handrail_types\": [\"30 in\", \"module rail\"], \"mount_search_m\": 0.04, "
      "\"mount_bay_min_m\": 0.3}",
      "t.json", &two, &error));
  assert_int_equal(two.handrail_type_count, 2);
  assert_string_equal(two.handrail_types[0].name, "30 in");
  assert_near(two.handrail_types[1].bar_length_m, 1.0, 1e-6);
  assert_near(two.mount_search_m, 0.04, 1e-6);
  assert_near(two.mount_bay_min_m, 0.3, 1e-6);
  estimator::DetectorConfig none;
  assert_true(
      estimator::parse_detector_config("{\"handrail_types\": []}", "n.json", &none, &error));
  assert_int_equal(none.handrail_type_count, 0);
  assert_true(none.plane_faces_normal);
  assert_true(
      estimator::parse_detector_config("{\"plane_faces_normal\": false}", "p.json", &none, &error));
  assert_false(none.plane_faces_normal);
  assert_true(none.track_beside);
  assert_true(estimator::parse_detector_config(
      "{\"track_beside\": false, \"track_beside_min_pixels\": 30}", "t.json", &none, &error));
  assert_false(none.track_beside);
  assert_int_equal(none.track_beside_min_pixels, 30);
  assert_true(none.cross_faces_wall);
  assert_true(
      estimator::parse_detector_config("{\"cross_faces_wall\": false}", "f.json", &none, &error));
  assert_false(none.cross_faces_wall);
  assert_false(none.bar_first);
  assert_true(estimator::parse_detector_config("{\"bar_first\": true}", "b.json", &none, &error));
  assert_true(none.bar_first);

  struct Case {
    const char* text;
    const char* error;
  } cases[] = {
      {"{\n \"line_iterations\": 0\n}",
       "c.json:2: \"line_iterations\" is out of range or inconsistent with the other settings"},
      {"{\n \"speed\": 3\n}", "c.json:2: unknown key \"speed\""},
      {"{\n \"plane_inlier_m\": \"big\"\n}", "c.json:2: \"plane_inlier_m\" must be a number"},
      {"{\n \"plane_faces_normal\": 1\n}",
       "c.json:2: \"plane_faces_normal\" must be true or false"},
      {"{\n \"track_beside\": \"yes\"\n}", "c.json:2: \"track_beside\" must be true or false"},
      {"{\n \"cross_faces_wall\": 0\n}", "c.json:2: \"cross_faces_wall\" must be true or false"},
      {"{\n \"bar_first\": \"on\"\n}", "c.json:2: \"bar_first\" must be true or false"},
      {"{\n \"handrail\": {\"kind\": \"oval\"}\n}",
       "c.json:2: \"handrail.kind\" must be \"iss\" or \"round\""},
      {"{\n \"min_line_inliers\": 2.5\n}",
       "c.json:2: \"min_line_inliers\" must be a non-negative integer"},
      {"{\n \"handrail_types\": [\"21.5 in\", \"9 in\"]\n}",
       "c.json:2: \"handrail_types\": unknown handrail type \"9 in\"; known: \"8.5 in\", "
       "\"21.5 in\", \"30 in\", \"41.5 in\", \"module rail\""},
      {"{\n \"handrail_types\": [\"30 in\",\n \"30 in\"]\n}",
       "c.json:3: \"handrail_types\": \"30 in\" is listed twice"},
      {"{\n \"handrail_types\": \"30 in\"\n}",
       "c.json:2: \"handrail_types\" must be an array of type names (\"8.5 in\", \"21.5 in\", "
       "\"30 in\", \"41.5 in\", \"module rail\")"},
      {"{\n \"max_mount_hypotheses\": 9\n}",
       "c.json:2: \"max_mount_hypotheses\" is out of range or inconsistent with the other "
       "settings"},
      {"{\n\n",
       "c.json:3: syntax error while parsing object key - unexpected end of input; expected "
       "string literal"},
  };
  for (const Case& c : cases) {
    estimator::DetectorConfig before;
    assert_false(estimator::parse_detector_config(c.text, "c.json", &before, &error));
    if (error != c.error) print_error("got: %s\nwant: %s\n", error.c_str(), c.error);
    assert_string_equal(error.c_str(), c.error);
  }
}

void test_detection_json(void**) {
  estimator::HandrailDetection d;
  d.status = estimator::DetectStatus::kNoLine;
  d.processing_time_us = 1250;
  assert_string_equal(
      tools::detection_to_json("a\"b.pcd", d).c_str(),
      "{\"frame\":\"a\\\"b.pcd\",\"frame_id\":0,\"state\":\"NH\",\"reason\":\"NO_LINE\",\"first_"
      "line\":\"ACCEPTED\",\"mounts\":{\"found\":0,\"tried\":0},\"time_ms\":1.250}");
  d.status = estimator::DetectStatus::kFound;
  d.state = estimator::HandrailState::kOneEnd;
  d.end_seen[1] = true;
  d.ends_cam[1] = Eigen::Vector3f(1, 2, 3);
  d.R_cam_handrail = d.R_cam_target = Eigen::Matrix3f::Identity();
  const std::string s = tools::detection_to_json("f.pcd", d);
  assert_true(s.find("\"state\":\"OE\"") != std::string::npos);
  assert_true(s.find("\"ends\":[[1.00000,2.00000,3.00000]]") != std::string::npos);
  assert_true(s.find("\"target_rotation\":[[1.00000,0.00000,0.00000],") != std::string::npos);
  // One end seen: the length is unknown, no type is named.
  assert_true(s.find("\"length_m\":0.0000") != std::string::npos);
  assert_true(s.find("\"iss_type\":null") != std::string::npos);
  // End to end, matched to a type, on a seat track 1.3 cm proud.
  d.state = estimator::HandrailState::kBothEnds;
  d.end_seen[0] = true;
  d.handrail_type = 1;
  d.handrail_type_name = "21.5 in";
  d.length_m = 0.531f;
  d.visible_length_m = 0.525f;
  d.mount_offset_m = 0.013f;
  const std::string be = tools::detection_to_json("f.pcd", d);
  assert_true(be.find("\"visible_length_m\":0.5250,\"length_m\":0.5310,\"mount_offset_m\":0.0130,"
                      "\"iss_type\":\"21.5 in\"") != std::string::npos);
}

// hrdetect --mounts: the dominant plane and the surfaces and mounts
// measured from it, only as many as were found.
void test_mounts_json(void**) {
  estimator::Plane plane;
  plane.normal = Eigen::Vector3f(0.0f, 0.6f, -0.8f);
  plane.d = 0.6125f;
  estimator::MountHypotheses m;
  m.surface_count = 2;
  m.surface_m[0] = -0.0203f;
  m.surface_m[1] = 0.0017f;
  m.surface_m[2] = 0.5f;  // not found: not written
  m.count = 2;
  m.offset_m[0] = 0.0147f;
  m.front_pixels[0] = 296;
  m.offset_m[1] = 0.0283f;  // read off a bar-front peak
  m.front_pixels[1] = 410;
  m.front_peak_count = 1;
  m.dominant_front_pixels = 2;
  assert_string_equal(tools::mounts_to_json(plane, m).c_str(),
                      "{\"plane\":{\"normal\":[0.00000,0.60000,-0.80000],\"d_m\":0.6125},"
                      "\"surfaces_m\":[-0.0203,0.0017],\"offsets_m\":[0.0147,0.0283],"
                      "\"front_pixels\":[296,410],\"plane_front_pixels\":2,"
                      "\"front_peak_mounts\":1}");
  // None found (a frame without a plane): empty lists.
  assert_string_equal(
      tools::mounts_to_json(estimator::Plane{}, estimator::MountHypotheses{}).c_str(),
      "{\"plane\":{\"normal\":[0.00000,0.00000,0.00000],\"d_m\":0.0000},"
      "\"surfaces_m\":[],\"offsets_m\":[],\"front_pixels\":[],"
      "\"plane_front_pixels\":0,\"front_peak_mounts\":0}");
}

void test_image_text_and_png(void**) {
  tools::Image img(40, 12);
  img.text(1, 1, "OK 1", {255, 255, 255});
  int lit = 0;
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 40; ++x) lit += img.get(x, y).r > 0;
  assert_true(lit > 20);
  // A line with an end a trillion pixels away (a point just in front of
  // the camera, projected) is drawn where it crosses the picture, and only
  // there; one wholly outside, or not finite, draws nothing.
  tools::Image lines(40, 12);
  lines.line(2.0, 6.0, 2.0e12, 6.0, {255, 0, 0});
  lines.line(-5.0, -5.0, -1.0e12, 3.0, {0, 255, 0});
  lines.line(NAN, 1.0, 3.0, 1.0, {0, 255, 0});
  int red = 0, green = 0;
  for (int y = 0; y < 12; ++y) {
    for (int x = 0; x < 40; ++x) {
      red += lines.get(x, y).r > 0;
      green += lines.get(x, y).g > 0;
    }
  }
  assert_int_equal(red, 38);  // x 2 .. 39 on row 6
  assert_true(lines.get(39, 6).r > 0 && lines.get(1, 6).r == 0);
  assert_int_equal(green, 0);
  std::string error;
  assert_false(img.write_png("/nonexistent/dir/x.png", &error));
  assert_string_equal(error.c_str(), "/nonexistent/dir/x.png: cannot create the PNG file");
}

// A tool's output folder is made with its missing parents; a file standing
// where a folder should be is refused with its path named.
// Command-line numbers: the whole text, within its range.
void test_whole_numbers(void**) {
  long long v = 0;
  std::string why;
  assert_true(tools::parse_whole_number("25", 1, 100, &v, &why));
  assert_int_equal(v, 25);
  for (const char* bad : {"abc", "2x", "", "-3", "0", "101", "99999999999999999999", " 5"}) {
    assert_false(tools::parse_whole_number(bad, 1, 100, &v, &why));
    assert_true(why.find(std::string("'") + bad + "'") != std::string::npos);
  }
  assert_int_equal(v, 25);
}

void test_output_dir(void**) {
  char base_template[] = "/tmp/hrp-outdir-XXXXXX";
  const char* base = mkdtemp(base_template);
  assert_non_null(base);
  const std::string root(base);
  std::string error;
  const std::string nested = root + "/a/b/c";
  assert_true(tools::make_output_dir(nested, &error));
  struct stat st {};
  assert_int_equal(stat(nested.c_str(), &st), 0);
  assert_true(S_ISDIR(st.st_mode));
  assert_true(tools::make_output_dir(nested, &error));  // there already: fine

  const std::string file = root + "/a/file";
  FILE* f = std::fopen(file.c_str(), "w");
  assert_non_null(f);
  std::fclose(f);
  error.clear();
  assert_false(tools::make_output_dir(file, &error));
  assert_true(error.find(file) != std::string::npos);
  error.clear();
  assert_false(tools::make_output_dir(file + "/below", &error));
  assert_true(error.find(file + "/below") != std::string::npos);
  error.clear();
  assert_false(tools::make_output_dir("", &error));
  assert_false(error.empty());

  std::remove(file.c_str());
  for (const std::string& d : {nested, root + "/a/b", root + "/a", root}) rmdir(d.c_str());
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_config_file), cmocka_unit_test(test_detection_json),
      cmocka_unit_test(test_mounts_json), cmocka_unit_test(test_image_text_and_png),
      cmocka_unit_test(test_output_dir),  cmocka_unit_test(test_whole_numbers),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
