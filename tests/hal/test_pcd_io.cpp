// PCD reading and writing: round trips and every malformed-file case.
#include <cmath>
#include <string>
#include <vector>

#include "cmocka_cpp.hpp"
#include "hal/pcd_io.hpp"
#include "test_data.hpp"

namespace {

std::vector<hal::DepthPoint> sample_points(std::uint32_t w, std::uint32_t h) {
  std::vector<hal::DepthPoint> pts(w * h);
  for (std::uint32_t i = 0; i < w * h; ++i) {
    pts[i] = {0.01f * static_cast<float>(i % w),     -0.02f * static_cast<float>(i / w),
              0.5f + 0.001f * static_cast<float>(i), 0.002f,
              static_cast<std::uint16_t>(100 + i),   static_cast<std::uint8_t>(200)};
  }
  pts[3].confidence = 0;  // invalid by confidence
  return pts;
}

void round_trip(hal::PcdEncoding encoding) {
  const std::vector<hal::DepthPoint> pts = sample_points(4, 3);
  const hal::DepthFrame frame{0, 0, 4, 3, pts.data()};
  hal::PcdFrame back;
  std::string error;
  assert_true(hal::parse_pcd(hal::encode_pcd(frame, encoding), "mem.pcd", &back, &error));
  assert_int_equal(back.width, 4);
  assert_int_equal(back.height, 3);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (i == 3) {
      assert_int_equal(back.points[i].confidence, 0);
      assert_false(hal::is_valid(back.points[i]));
      continue;
    }
    assert_near(back.points[i].x_m, pts[i].x_m, 1e-6);
    assert_near(back.points[i].z_m, pts[i].z_m, 1e-6);
    assert_near(back.points[i].noise_m, pts[i].noise_m, 1e-7);
    assert_int_equal(back.points[i].gray_value, pts[i].gray_value);
    assert_int_equal(back.points[i].confidence, 200);
  }
}

void test_round_trip_ascii(void**) {
  round_trip(hal::PcdEncoding::kAscii);
}
void test_round_trip_binary(void**) {
  round_trip(hal::PcdEncoding::kBinary);
}

void test_reads_other_layouts(void**) {
  // Another field order, an extra field with COUNT 3, doubles, no
  // confidence: NaN and z = 0 are the invalid points.
  const std::string text =
      "# written by another tool\nVERSION .7\nFIELDS rgb z normal y x\nSIZE 4 8 4 4 4\nTYPE U F F "
      "F F\n"
      "COUNT 1 1 3 1 1\nWIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
      "7 1.5 0 0 1 0.25 0.5\n7 nan 0 0 1 0 0\n7 0 0 0 1 0.1 0.1\n7 2 0 0 1 -0.5 -0.25\n";
  hal::PcdFrame f;
  std::string error;
  assert_true(hal::parse_pcd(text, "other.pcd", &f, &error));
  assert_near(f.points[0].x_m, 0.5, 1e-6);
  assert_near(f.points[0].y_m, 0.25, 1e-6);
  assert_near(f.points[0].z_m, 1.5, 1e-6);
  assert_int_equal(f.points[0].confidence, 255);
  assert_false(hal::is_valid(f.points[1]));
  assert_false(hal::is_valid(f.points[2]));
  assert_true(hal::is_valid(f.points[3]));
}

void test_reads_the_recorded_frame(void**) {
  hal::PcdFrame f;
  std::string error;
  assert_true(hal::read_pcd(testing_support::data_path("table2-iss-1.pcd"), &f, &error));
  assert_int_equal(f.width, 224);
  assert_int_equal(f.height, 171);
  const hal::DepthFrame view = f.view();
  assert_true(hal::count_valid(view) > 30000);
}

void test_malformed_files_are_named_and_explained(void**) {
  const std::string good_header =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 2\nPOINTS "
      "4\n";
  struct Case {
    std::string text;
    const char* error;
  } cases[] = {
      {"VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nDATA ascii\n",
       "bad.pcd: SIZE has 2 entries for 3 fields"},
      {"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 5\nDATA "
       "ascii\n",
       "bad.pcd: POINTS 5 does not equal WIDTH x HEIGHT 4"},
      {"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4\nHEIGHT 1\nDATA ascii\n",
       "bad.pcd: not an organized cloud (HEIGHT 1); depth frames are organized"},
      {"VERSION 0.7\nFIELDS a b c\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nDATA ascii\n",
       "bad.pcd: FIELDS must include x, y and z"},
      {"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\nWIDTH 2\nHEIGHT 2\nDATA ascii\n",
       "bad.pcd: field 'z' has unsupported TYPE Q with SIZE 4"},
      {"VERSION 0.7\nFROBNICATE 3\n",
       "bad.pcd: header line 2 (FROBNICATE): unknown header keyword"},
      {"VERSION 0.7\nFIELDS x y z\nWIDTH two\n",
       "bad.pcd: header line 3 (WIDTH): expected one non-negative integer"},
      {"VERSION 0.7\nFIELDS x y z\n", "bad.pcd: header ends before a DATA line"},
      {good_header + "DATA binary_compressed\n",
       "bad.pcd: DATA binary_compressed is not supported (ascii or binary)"},
      {good_header + "DATA ascii\n1 2 3\n1 2 3\n1 2\n",
       "bad.pcd: line 12: expected 3 numbers, found 2"},
      {good_header + "DATA ascii\n1 2 3\n1 2 3\n", "bad.pcd: ascii data truncated: 2 of 4 points"},
      {good_header + "DATA ascii\n1 2 3\n1 x 3\n1 2 3\n1 2 3\n",
       "bad.pcd: line 11: expected 3 numbers, found 1"},
      {good_header + "DATA binary\n" + std::string(40, '\0'),
       "bad.pcd: binary data truncated: 40 bytes for 4 points of 12 bytes"},
  };
  for (const Case& c : cases) {
    hal::PcdFrame f;
    std::string error;
    assert_false(hal::parse_pcd(c.text, "bad.pcd", &f, &error));
    if (error != c.error) print_error("got: %s\nwant: %s\n", error.c_str(), c.error);
    assert_string_equal(error.c_str(), c.error);
  }
  hal::PcdFrame f;
  std::string error;
  assert_false(hal::read_pcd("/nonexistent/x.pcd", &f, &error));
  assert_string_equal(error.c_str(), "/nonexistent/x.pcd: cannot open file");
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_round_trip_ascii),
      cmocka_unit_test(test_round_trip_binary),
      cmocka_unit_test(test_reads_other_layouts),
      cmocka_unit_test(test_reads_the_recorded_frame),
      cmocka_unit_test(test_malformed_files_are_named_and_explained),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
