// PCD reading and writing: round trips, files the Point Cloud Library wrote
// (tests/data/pcl, see its README.md), and every malformed-file case.
//
// `formats_pcd_io --write-sources DIR` writes the files the PCL fixtures
// were converted from, and exits.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "cmocka_cpp.hpp"
#include "formats/pcd_io.hpp"
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

// The frames the PCL fixtures were made from (changing this means making
// tests/data/pcl again). Every value is a short binary fraction, exact in a
// float and in PCL's ascii output, so that points are compared exactly; some
// points are invalid (NaN on disk). Depth changes slowly across the frame so
// that PCL's normal estimation finds normals away from the invalid points.
std::vector<hal::DepthPoint> fixture_points(std::uint32_t w, std::uint32_t h) {
  std::vector<hal::DepthPoint> pts(static_cast<std::size_t>(w) * h);
  for (std::uint32_t r = 0; r < h; ++r) {
    for (std::uint32_t c = 0; c < w; ++c) {
      const std::uint32_t i = r * w + c;
      hal::DepthPoint& p = pts[i];
      p.x_m = (static_cast<float>(c) - static_cast<float>(w / 2)) / 16.0f;
      p.y_m = (static_cast<float>(r) - static_cast<float>(h / 2)) / 16.0f;
      p.z_m = 1.0f + static_cast<float>(c) / 256.0f + static_cast<float>(r) / 128.0f;
      p.noise_m = static_cast<float>(1 + i % 4) / 256.0f;
      p.gray_value = static_cast<std::uint16_t>(100 + i);
      p.confidence = static_cast<std::uint8_t>(1 + (i * 37) % 255);
      if (i % 29 == 5) p.confidence = 0;  // invalid: written as NaN
    }
  }
  return pts;
}

// What reading back a point our writer wrote must give.
hal::DepthPoint as_read_back(const hal::DepthPoint& p) {
  if (hal::is_valid(p)) return p;
  return hal::DepthPoint{0.0f, 0.0f, 0.0f, 0.0f, p.gray_value, 0};
}

void assert_same_point(const hal::DepthPoint& got, const hal::DepthPoint& want, const char* what,
                       std::size_t i) {
  const bool same = got.x_m == want.x_m && got.y_m == want.y_m && got.z_m == want.z_m &&
                    got.noise_m == want.noise_m && got.gray_value == want.gray_value &&
                    got.confidence == want.confidence;
  if (!same) {
    print_error(
        "%s point %zu: got (%.9g %.9g %.9g noise %.9g gray %u conf %u), want (%.9g %.9g "
        "%.9g noise %.9g gray %u conf %u)\n",
        what, i, got.x_m, got.y_m, got.z_m, got.noise_m, got.gray_value, got.confidence, want.x_m,
        want.y_m, want.z_m, want.noise_m, want.gray_value, want.confidence);
  }
  assert_true(same);
}

// Our writer's frame, read back from `path` (a file PCL or our writer made).
void assert_reads_fixture_frame(const std::string& path, std::uint32_t w, std::uint32_t h) {
  formats::PcdFrame f;
  std::string error;
  if (!formats::read_pcd(path, &f, &error)) print_error("%s\n", error.c_str());
  assert_true(error.empty());
  assert_int_equal(f.width, w);
  assert_int_equal(f.height, h);
  const std::vector<hal::DepthPoint> want = fixture_points(w, h);
  assert_int_equal(f.points.size(), want.size());
  std::size_t invalid = 0;
  for (std::size_t i = 0; i < want.size(); ++i) {
    assert_same_point(f.points[i], as_read_back(want[i]), path.c_str(), i);
    if (!hal::is_valid(want[i])) ++invalid;
  }
  assert_true(invalid > 0);
}

// The other-fields source: another field order, a double, COUNT 3, integer
// fields, no noise or confidence; NaN and z = 0 points are invalid.
struct OtherPoint {
  std::uint32_t rgb;
  double y, x, z;
  std::uint16_t intensity;
  std::int32_t label;
};

OtherPoint other_point(std::uint32_t w, std::uint32_t h, std::uint32_t i) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::uint32_t r = i / w, c = i % w;
  OtherPoint p{0x00ff8000u + i,
               (static_cast<double>(r) - h / 2) / 16.0,
               (static_cast<double>(c) - w / 2) / 16.0,
               1.0 + i / 64.0,
               static_cast<std::uint16_t>(500 + 3 * i),
               -static_cast<std::int32_t>(i)};
  if (i % 7 == 2) p.x = p.y = p.z = nan;
  if (i % 11 == 4) p.z = 0.0;
  return p;
}

constexpr std::uint32_t kOtherWidth = 8, kOtherHeight = 6;

std::string other_fields_ascii() {
  std::string s =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
      "FIELDS rgb y x normal z intensity label\nSIZE 4 4 4 4 8 2 4\nTYPE U F F F F U I\n"
      "COUNT 1 1 1 3 1 1 1\nWIDTH 8\nHEIGHT 6\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 48\nDATA ascii\n";
  char line[200];
  for (std::uint32_t i = 0; i < kOtherWidth * kOtherHeight; ++i) {
    const OtherPoint p = other_point(kOtherWidth, kOtherHeight, i);
    std::snprintf(line, sizeof line, "%u %.9g %.9g 0 0 -1 %.17g %u %d\n", p.rgb, p.y, p.x, p.z,
                  static_cast<unsigned>(p.intensity), static_cast<int>(p.label));
    s += line;
  }
  return s;
}

void assert_reads_other_fields(const std::string& path) {
  formats::PcdFrame f;
  std::string error;
  if (!formats::read_pcd(path, &f, &error)) print_error("%s\n", error.c_str());
  assert_true(error.empty());
  assert_int_equal(f.width, kOtherWidth);
  assert_int_equal(f.height, kOtherHeight);
  for (std::uint32_t i = 0; i < kOtherWidth * kOtherHeight; ++i) {
    const OtherPoint p = other_point(kOtherWidth, kOtherHeight, i);
    hal::DepthPoint want{0.0f, 0.0f, 0.0f, 0.0f, p.intensity, 0};
    if (std::isfinite(p.z) && p.z > 0.0)
      want = {static_cast<float>(p.x),
              static_cast<float>(p.y),
              static_cast<float>(p.z),
              0.0f,
              p.intensity,
              255};
    assert_same_point(f.points[i], want, path.c_str(), i);
  }
}

template <typename T>
std::string raw_bytes(const std::vector<T>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

// Our fields as binary with 4 bytes of padding after z, named "_" as PCL
// names the padding of its point types.
std::string padded_binary(std::uint32_t w, std::uint32_t h) {
  std::string s =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
      "FIELDS x y z _ intensity noise confidence\nSIZE 4 4 4 1 4 4 1\n"
      "TYPE F F F U F F U\nCOUNT 1 1 1 4 1 1 1\nWIDTH " +
      std::to_string(w) + "\nHEIGHT " + std::to_string(h) + "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
      std::to_string(w * h) + "\nDATA binary\n";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const hal::DepthPoint& p : fixture_points(w, h)) {
    const bool valid = hal::is_valid(p);
    const std::vector<float> xyz = {valid ? p.x_m : nan, valid ? p.y_m : nan, valid ? p.z_m : nan};
    const std::vector<float> gray_noise = {static_cast<float>(p.gray_value),
                                           valid ? p.noise_m : nan};
    s += raw_bytes(xyz) + std::string(4, '\xaa') + raw_bytes(gray_noise);
    s.push_back(static_cast<char>(valid ? p.confidence : 0));
  }
  return s;
}

bool write_file(const std::string& path, const std::string& bytes) {
  std::FILE* out = std::fopen(path.c_str(), "wb");
  if (!out) return false;
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), out) == bytes.size();
  return std::fclose(out) == 0 && ok;
}

// LZF data made only of literal runs (a control byte of length - 1, then up
// to 32 bytes): valid for any decoder, and independent of our writer.
std::string lzf_literals(const std::string& raw) {
  std::string s;
  for (std::size_t k = 0; k < raw.size(); k += 32) {
    const std::size_t len = std::min<std::size_t>(32, raw.size() - k);
    s.push_back(static_cast<char>(len - 1));
    s.append(raw, k, len);
  }
  return s;
}

std::string le_u32(std::uint32_t v) {
  std::string s;
  for (int shift = 0; shift < 32; shift += 8) s.push_back(static_cast<char>((v >> shift) & 0xff));
  return s;
}

void round_trip(formats::PcdEncoding encoding) {
  const std::vector<hal::DepthPoint> pts = sample_points(4, 3);
  const hal::DepthFrame frame{0, 0, 4, 3, pts.data()};
  formats::PcdFrame back;
  std::string error;
  assert_true(formats::parse_pcd(formats::encode_pcd(frame, encoding), "mem.pcd", &back, &error));
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
  round_trip(formats::PcdEncoding::kAscii);
}
void test_round_trip_binary(void**) {
  round_trip(formats::PcdEncoding::kBinary);
}
void test_round_trip_binary_compressed(void**) {
  round_trip(formats::PcdEncoding::kBinaryCompressed);
}

// Our binary_compressed writer through a file and back: every point equal,
// and the data really compressed and laid out field by field.
void test_binary_compressed_file_round_trip(void**) {
  const std::vector<hal::DepthPoint> pts = fixture_points(16, 12);
  const hal::DepthFrame frame{0, 0, 16, 12, pts.data()};
  const std::string bytes = formats::encode_pcd(frame, formats::PcdEncoding::kBinaryCompressed);
  const std::string data_line = "DATA binary_compressed\n";
  const std::size_t data_at = bytes.find(data_line);
  assert_true(data_at != std::string::npos);
  const std::size_t sizes_at = data_at + data_line.size();
  assert_true(bytes.size() >= sizes_at + 8);
  const auto u32_at = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int k = 3; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(bytes[at + k]);
    return v;
  };
  assert_int_equal(u32_at(sizes_at + 4), 16 * 12 * 21);
  assert_int_equal(u32_at(sizes_at), bytes.size() - sizes_at - 8);
  assert_true(u32_at(sizes_at) < 16 * 12 * 21);

  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp ? tmp : "/tmp") + "/formats_pcd_io_round_trip.pcd";
  std::string error;
  assert_true(formats::write_pcd(path, frame, formats::PcdEncoding::kBinaryCompressed, &error));
  assert_reads_fixture_frame(path, 16, 12);
  std::remove(path.c_str());
}

void test_reads_other_layouts(void**) {
  // Another field order, an extra field with COUNT 3, doubles, no
  // confidence: NaN and z = 0 are the invalid points.
  const std::string text =
      "# written by another tool\nVERSION .7\nFIELDS rgb z normal y x\nSIZE 4 8 4 4 4\nTYPE U F F "
      "F F\n"
      "COUNT 1 1 3 1 1\nWIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
      "7 1.5 0 0 1 0.25 0.5\n7 nan 0 0 1 0 0\n7 0 0 0 1 0.1 0.1\n7 2 0 0 1 -0.5 -0.25\n";
  formats::PcdFrame f;
  std::string error;
  assert_true(formats::parse_pcd(text, "other.pcd", &f, &error));
  assert_near(f.points[0].x_m, 0.5, 1e-6);
  assert_near(f.points[0].y_m, 0.25, 1e-6);
  assert_near(f.points[0].z_m, 1.5, 1e-6);
  assert_int_equal(f.points[0].confidence, 255);
  assert_false(hal::is_valid(f.points[1]));
  assert_false(hal::is_valid(f.points[2]));
  assert_true(hal::is_valid(f.points[3]));
}

// binary_compressed as PCL's reader takes it: padding fields "_" hold no
// bytes, a COUNT 3 field is one plane of 3 values per point, any order.
void test_reads_compressed_padding_and_counts(void**) {
  const std::vector<float> z = {1.0f, 2.0f, NAN, 0.5f};
  const std::vector<float> normal = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const std::vector<double> x = {0.25, -0.25, 0.0, 0.125};
  const std::vector<std::uint8_t> conf = {9, 0, 9, 200};
  const std::vector<float> y = {0.5f, 0.5f, 0.0f, -1.0f};
  const std::string raw =
      raw_bytes(z) + raw_bytes(normal) + raw_bytes(x) + raw_bytes(conf) + raw_bytes(y);
  const std::string stream = lzf_literals(raw);
  const std::string text =
      "VERSION 0.7\nFIELDS z _ normal x confidence y _\nSIZE 4 1 4 8 1 4 1\n"
      "TYPE F U F F U F U\nCOUNT 1 3 3 1 1 1 2\nWIDTH 2\nHEIGHT 2\nPOINTS 4\n"
      "DATA binary_compressed\n" +
      le_u32(static_cast<std::uint32_t>(stream.size())) +
      le_u32(static_cast<std::uint32_t>(raw.size())) + stream;
  formats::PcdFrame f;
  std::string error;
  if (!formats::parse_pcd(text, "pad.pcd", &f, &error)) print_error("%s\n", error.c_str());
  assert_true(error.empty());
  assert_same_point(f.points[0], {0.25f, 0.5f, 1.0f, 0.0f, 0, 9}, "pad.pcd", 0);
  assert_same_point(f.points[1], {0, 0, 0, 0, 0, 0}, "pad.pcd", 1);  // confidence 0
  assert_same_point(f.points[2], {0, 0, 0, 0, 0, 0}, "pad.pcd", 2);  // NaN
  assert_same_point(f.points[3], {0.125f, -1.0f, 0.5f, 0.0f, 0, 200}, "pad.pcd", 3);
}

void test_reads_the_recorded_frame(void**) {
  formats::PcdFrame f;
  std::string error;
  assert_true(formats::read_pcd(testing_support::data_path("table2-iss-1.pcd"), &f, &error));
  assert_int_equal(f.width, 224);
  assert_int_equal(f.height, 171);
  const hal::DepthFrame view = f.view();
  assert_true(hal::count_valid(view) > 30000);
}

// Files PCL 1.13 wrote (tests/data/pcl/README.md says how).
void test_reads_pcl_binary_compressed(void**) {
  assert_reads_fixture_frame(testing_support::data_path("pcl/pcl-16x12-binary_compressed.pcd"), 16,
                             12);
  assert_reads_other_fields(
      testing_support::data_path("pcl/pcl-other-fields-binary_compressed.pcd"));
}

// Padding as PCL writes it: "_" with its bytes in binary, left out of
// binary_compressed. And PCL's normal estimation output: normal_x normal_y
// normal_z curvature before our fields. All must give our frame back.
void test_reads_pcl_padding_and_normals(void**) {
  assert_reads_fixture_frame(testing_support::data_path("pcl/pcl-padded-8x6-binary.pcd"), 8, 6);
  assert_true(
      testing_support::read_text(testing_support::data_path("pcl/pcl-padded-8x6-binary.pcd"))
          .find("FIELDS x y z _ intensity") != std::string::npos);
  assert_reads_fixture_frame(testing_support::data_path("pcl/pcl-padded-8x6-binary_compressed.pcd"),
                             8, 6);
  assert_reads_fixture_frame(
      testing_support::data_path("pcl/pcl-normals-16x12-binary_compressed.pcd"), 16, 12);
}

// PCL read what our writer wrote: the committed file our writer made, and
// PCL's ascii conversion of it, both give our encoder's input back.
void test_pcl_reads_our_binary_compressed(void**) {
  assert_reads_fixture_frame(testing_support::data_path("pcl/ours-8x6-binary_compressed.pcd"), 8,
                             6);
  const std::string ascii = testing_support::data_path("pcl/pcl-ascii-from-ours-8x6.pcd");
  assert_true(testing_support::read_text(ascii).find("DATA ascii\n") != std::string::npos);
  assert_reads_fixture_frame(ascii, 8, 6);
}

void test_malformed_files_are_named_and_explained(void**) {
  const std::string good_header =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 2\nPOINTS "
      "4\n";
  const std::string huge_header =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4096\nHEIGHT 4096\n";
  // 4 points of x y z: 48 bytes, here as 12 floats.
  std::vector<float> xyz(12, 1.0f);
  const std::string raw = raw_bytes(xyz);
  const std::string stream = lzf_literals(raw);
  const std::string compressed = "DATA binary_compressed\n";
  auto sizes = [](std::size_t compressed_bytes, std::size_t uncompressed_bytes) {
    return le_u32(static_cast<std::uint32_t>(compressed_bytes)) +
           le_u32(static_cast<std::uint32_t>(uncompressed_bytes));
  };
  // A back reference before the start of the output: corrupt.
  const std::string corrupt = std::string("\x20\x00", 2) + stream;
  const std::string short_stream = lzf_literals(raw.substr(0, 40));
  const std::string long_stream = lzf_literals(raw + std::string(8, 'x'));
  struct Case {
    std::string text;
    std::string error;
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
      {good_header + "DATA binary_lzma\n",
       "bad.pcd: DATA binary_lzma is not supported (ascii, binary or binary_compressed)"},
      {good_header + "DATA ascii\n1 2 3\n1 2 3\n1 2\n",
       "bad.pcd: line 12: expected 3 numbers, found 2"},
      {good_header + "DATA ascii\n1 2 3\n1 2 3\n", "bad.pcd: ascii data truncated: 2 of 4 points"},
      {good_header + "DATA ascii\n1 2 3\n1 x 3\n1 2 3\n1 2 3\n",
       "bad.pcd: line 11: expected 3 numbers, found 1"},
      {good_header + "DATA binary\n" + std::string(40, '\0'),
       "bad.pcd: binary data truncated: 40 bytes for 4 points of 12 bytes"},
      // Headers claiming more than the file holds, refused before any
      // room is made for their points.
      {huge_header + "DATA binary\n" + std::string(40, '\0'),
       "bad.pcd: binary data truncated: 40 bytes for 16777216 points of 12 bytes"},
      {huge_header + "DATA ascii\n1 2 3\n1 2 3\n",
       "bad.pcd: ascii data truncated: 2 of 16777216 points"},
      {"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4097\nHEIGHT 4096\n" + compressed +
           sizes(stream.size(), raw.size()) + stream,
       "bad.pcd: WIDTH x HEIGHT 4097 x 4096 is 16781312 points, over the limit of 16777216"},
      // binary_compressed.
      {good_header + compressed + std::string("\x30\x00\x00", 3),
       "bad.pcd: binary_compressed data truncated: 3 "
       "bytes after the header, need 8 for the "
       "compressed and uncompressed sizes"},
      {good_header + compressed + sizes(stream.size(), 300u << 20) + stream,
       "bad.pcd: binary_compressed uncompressed size 314572800 bytes is over the limit of "
       "268435456 bytes"},
      {huge_header + compressed + sizes(stream.size(), 4096u * 4096u * 12u) + stream,
       "bad.pcd: binary_compressed uncompressed size 201326592 bytes is more than LZF can "
       "expand 50 compressed bytes to (88 times as many)"},
      {good_header + compressed + sizes(stream.size(), 36) + stream,
       "bad.pcd: binary_compressed uncompressed size 36 bytes does not equal 4 points x 12 bytes "
       "= 48"},
      {good_header + compressed + sizes(stream.size() + 1, raw.size()) + stream,
       "bad.pcd: binary_compressed compressed size 51 bytes is more than the 50 bytes left in the "
       "file"},
      {good_header + compressed + sizes(0xffffffffu, raw.size()) + stream,
       "bad.pcd: binary_compressed compressed size 4294967295 bytes is more than the 50 bytes "
       "left in the file"},
      {good_header + compressed + sizes(corrupt.size(), raw.size()) + corrupt,
       "bad.pcd: LZF decompression failed: corrupt compressed data"},
      {good_header + compressed + sizes(short_stream.size(), raw.size()) + short_stream,
       "bad.pcd: LZF data decompressed to 40 bytes, not the uncompressed size 48 bytes"},
      {good_header + compressed + sizes(long_stream.size(), raw.size()) + long_stream,
       "bad.pcd: LZF data decompresses to more than the uncompressed size 48 bytes"},
  };
  for (const Case& c : cases) {
    formats::PcdFrame f;
    f.width = 77;  // a failed read leaves *out as it was
    std::string error;
    assert_false(formats::parse_pcd(c.text, "bad.pcd", &f, &error));
    if (error != c.error) print_error("got: %s\nwant: %s\n", error.c_str(), c.error.c_str());
    assert_string_equal(error.c_str(), c.error.c_str());
    assert_int_equal(f.width, 77);
  }
  formats::PcdFrame f;
  std::string error;
  assert_false(formats::read_pcd("/nonexistent/x.pcd", &f, &error));
  assert_string_equal(error.c_str(), "/nonexistent/x.pcd: cannot open (No such file or directory)");
}

// A file over read_pcd's limit is refused by its size, before it is read
// (sparse: it takes no disk space).
void test_refuses_a_file_over_the_size_limit(void**) {
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp ? tmp : "/tmp") + "/formats_pcd_io_huge.pcd";
  std::FILE* out = std::fopen(path.c_str(), "wb");
  assert_non_null(out);
  assert_int_equal(std::fseek(out, static_cast<long>(formats::kMaxPcdFileBytes), SEEK_SET), 0);
  assert_int_equal(std::fputc('\n', out), '\n');
  assert_int_equal(std::fclose(out), 0);
  formats::PcdFrame f;
  std::string error;
  assert_false(formats::read_pcd(path, &f, &error));
  std::remove(path.c_str());
  assert_true(error.rfind(path + ": ", 0) == 0);
  assert_true(error.find("over the limit") != std::string::npos);
}

// The files tests/data/pcl/README.md converts with PCL's tools.
int write_sources(const std::string& dir) {
  const std::vector<hal::DepthPoint> big = fixture_points(16, 12);
  const std::vector<hal::DepthPoint> small = fixture_points(8, 6);
  const hal::DepthFrame big_frame{0, 0, 16, 12, big.data()};
  const hal::DepthFrame small_frame{0, 0, 8, 6, small.data()};
  std::string error;
  const bool ok = formats::write_pcd(dir + "/ours-16x12-binary.pcd", big_frame,
                                     formats::PcdEncoding::kBinary, &error) &&
                  formats::write_pcd(dir + "/ours-16x12-binary_compressed.pcd", big_frame,
                                     formats::PcdEncoding::kBinaryCompressed, &error) &&
                  formats::write_pcd(dir + "/ours-8x6-binary.pcd", small_frame,
                                     formats::PcdEncoding::kBinary, &error) &&
                  formats::write_pcd(dir + "/ours-8x6-binary_compressed.pcd", small_frame,
                                     formats::PcdEncoding::kBinaryCompressed, &error);
  if (!ok) {
    std::fprintf(stderr, "formats_pcd_io: %s\n", error.c_str());
    return 1;
  }
  if (!write_file(dir + "/other-fields-8x6-ascii.pcd", other_fields_ascii()) ||
      !write_file(dir + "/padded-8x6-binary.pcd", padded_binary(8, 6))) {
    std::fprintf(stderr, "formats_pcd_io: cannot write in %s\n", dir.c_str());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::strcmp(argv[1], "--write-sources") == 0) return write_sources(argv[2]);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_round_trip_ascii),
      cmocka_unit_test(test_round_trip_binary),
      cmocka_unit_test(test_round_trip_binary_compressed),
      cmocka_unit_test(test_binary_compressed_file_round_trip),
      cmocka_unit_test(test_reads_other_layouts),
      cmocka_unit_test(test_reads_compressed_padding_and_counts),
      cmocka_unit_test(test_reads_the_recorded_frame),
      cmocka_unit_test(test_reads_pcl_binary_compressed),
      cmocka_unit_test(test_reads_pcl_padding_and_normals),
      cmocka_unit_test(test_pcl_reads_our_binary_compressed),
      cmocka_unit_test(test_malformed_files_are_named_and_explained),
      cmocka_unit_test(test_refuses_a_file_over_the_size_limit),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
