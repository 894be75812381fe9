// hrframes on real LCM log files written here, as fsw_app --publish-frames
// --log writes them: every depth frame comes out as a PCD file named by its
// frame id with its points as recorded, the estimates as JSON lines; a
// frame message that does not decode is named by its event and the others
// are still written; --frames picks a range; a file that is not a log, a
// log without frames and bad options are errors that say what to do.
//   argv[1]: the hrframes program
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "cmocka_cpp.hpp"
#include "formats/pcd_io.hpp"
#include "fsw_app/depth_frame_msg.hpp"
#include "hrp/depth_frame_t.hpp"
#include "hrp/handrail_estimate_t.hpp"
#include "test_data.hpp"

namespace {

std::string g_program;
std::string g_dir;

constexpr std::uint32_t kWidth = 4, kHeight = 3;

// Frame `id`: point k at (0.01 k, 0.001 id, 0.5 + 0.01 k) m, the last one
// invalid.
std::vector<hal::DepthPoint> frame_points(std::uint64_t id) {
  std::vector<hal::DepthPoint> p(kWidth * kHeight);
  for (std::size_t k = 0; k < p.size(); ++k) {
    p[k].x_m = 0.01f * static_cast<float>(k);
    p[k].y_m = 0.001f * static_cast<float>(id);
    p[k].z_m = 0.5f + 0.01f * static_cast<float>(k);
    p[k].noise_m = 0.002f;
    p[k].gray_value = static_cast<std::uint16_t>(100 + k);
    p[k].confidence = 255;
  }
  p.back().z_m = 0.0f;
  p.back().confidence = 0;
  return p;
}

class LogWriter {
 public:
  explicit LogWriter(const std::string& path) : log_(path, "w") { assert_true(log_.good()); }
  void write(const char* channel, const std::vector<std::uint8_t>& bytes) {
    lcm::LogEvent e{};
    e.eventnum = next_++;
    e.timestamp = 1000 * e.eventnum;
    e.channel = channel;
    e.datalen = static_cast<std::int32_t>(bytes.size());
    e.data = const_cast<std::uint8_t*>(bytes.data());
    assert_int_equal(log_.writeEvent(&e), 0);
  }
  template <typename Msg>
  void write_msg(const char* channel, const Msg& m) {
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
    assert_true(m.encode(buf.data(), 0, static_cast<int>(buf.size())) > 0);
    write(channel, buf);
  }
  void write_frame(std::uint64_t id) {
    const std::vector<hal::DepthPoint> p = frame_points(id);
    const hal::DepthFrame frame{id, static_cast<std::int64_t>(id) * 200000, kWidth, kHeight,
                                p.data()};
    hrp::depth_frame_t msg;
    fsw_app::reserve_points(&msg, p.size());
    fsw_app::to_msg(frame, &msg);
    write_msg("DEPTH_FRAME", msg);
  }

 private:
  lcm::LogFile log_;
  std::int64_t next_ = 0;
};

// A BE estimate of frame `id`: the bar along the camera's x (the handrail
// frame turned 90 deg about y, so its z axis, along the bar, is camera x).
hrp::handrail_estimate_t estimate(long id) {
  hrp::handrail_estimate_t m{};
  m.frame_id = id;
  m.state = hrp::handrail_estimate_t::STATE_BE;
  m.T_cam_handrail.position_m[2] = 0.6;
  m.T_cam_handrail.quat_wxyz[0] = std::sqrt(0.5);
  m.T_cam_handrail.quat_wxyz[2] = std::sqrt(0.5);
  m.bar_length_m = 0.55;
  m.inliers = 420;
  m.num_ends = 2;
  return m;
}

using Result = testing_support::RunOutput;

Result run(const std::vector<std::string>& args) {
  return testing_support::run_capturing(g_program, args, g_dir + "/out.txt");
}

void expect_in(const std::string& text, const std::string& want) {
  if (text.find(want) == std::string::npos) {
    fail_msg("expected \"%s\" in:\n%s", want.c_str(), text.c_str());
  }
}

bool exists(const std::string& path) {
  return access(path.c_str(), F_OK) == 0;
}

// The frames come back point for point (the invalid one invalid); the
// corrupt message between them is named by its event and skipped.
void test_frames_and_estimates_are_written(void**) {
  const std::string log = g_dir + "/run.lcmlog", out = g_dir + "/frames";
  {
    LogWriter w(log);
    w.write_frame(5);
    w.write_msg("HANDRAIL_ESTIMATE", estimate(5));
    w.write("DEPTH_FRAME", {1, 2, 3, 4, 5, 6, 7});  // event 2: truncated
    w.write_frame(6);
    w.write_msg("HANDRAIL_ESTIMATE", estimate(6));
    w.write_frame(17);
  }
  const Result r = run({log, "-o", out});
  assert_int_equal(r.exit_status, 1);
  expect_in(r.out, "event 2 (DEPTH_FRAME) does not decode: TRUNCATED");
  expect_in(r.out, "4 depth frames, 3 written");
  for (std::uint64_t id : {5u, 6u, 17u}) {
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%05llu.pcd", static_cast<unsigned long long>(id));
    formats::PcdFrame pcd;
    std::string error;
    assert_true(formats::read_pcd(out + name, &pcd, &error));
    assert_int_equal(pcd.width, kWidth);
    assert_int_equal(pcd.height, kHeight);
    const std::vector<hal::DepthPoint> want = frame_points(id);
    for (std::size_t k = 0; k + 1 < want.size(); ++k) {
      assert_float_equal(pcd.points[k].x_m, want[k].x_m, 1e-7);
      assert_float_equal(pcd.points[k].y_m, want[k].y_m, 1e-7);
      assert_float_equal(pcd.points[k].z_m, want[k].z_m, 1e-7);
      assert_int_equal(pcd.points[k].confidence, 255);
    }
    assert_int_equal(pcd.points.back().confidence, 0);
  }
  const std::string est = testing_support::read_text(out + "/estimates.jsonl");
  expect_in(est,
            "{\"frame_id\":5,\"state\":\"BE\",\"detect_status\":0,\"bar_length_m\":0.5500,"
            "\"inliers\":420,\"position\":[0.00000,0.00000,0.60000],"
            "\"axis\":[1.00000,0.00000,0.00000],\"num_ends\":2}\n");
  expect_in(est, "{\"frame_id\":6,");

  // A range: only those frames, and with a clean log exit status 0.
  const std::string clean = g_dir + "/clean.lcmlog", some = g_dir + "/some";
  {
    LogWriter w(clean);
    for (std::uint64_t id = 0; id < 4; ++id) w.write_frame(id);
    w.write_msg("HANDRAIL_ESTIMATE", estimate(1));
    w.write_msg("HANDRAIL_ESTIMATE", estimate(3));
  }
  const Result ranged = run({clean, "-o", some, "--frames", "1-2"});
  assert_int_equal(ranged.exit_status, 0);
  assert_false(exists(some + "/frame_00000.pcd"));
  assert_true(exists(some + "/frame_00001.pcd"));
  assert_true(exists(some + "/frame_00002.pcd"));
  assert_false(exists(some + "/frame_00003.pcd"));
  const std::string some_est = testing_support::read_text(some + "/estimates.jsonl");
  expect_in(some_est, "{\"frame_id\":1,");
  assert_true(some_est.find("\"frame_id\":3,") == std::string::npos);
}

void test_bad_input_is_named(void**) {
  const std::string not_a_log = g_dir + "/not_a_log.txt";
  std::ofstream(not_a_log) << "hello\n";
  Result r = run({not_a_log, "-o", g_dir + "/x"});
  // LCM's reader finds no event in it: a log without frames.
  assert_int_equal(r.exit_status, 1);
  expect_in(r.out, "record the run with fsw_app --publish-frames --log LOG");
  r = run({g_dir + "/missing.lcmlog", "-o", g_dir + "/y"});
  assert_int_equal(r.exit_status, 2);
  expect_in(r.out, "missing.lcmlog: cannot open as an LCM log");
  r = run({g_dir + "/missing.lcmlog"});
  assert_int_equal(r.exit_status, 2);
  expect_in(r.out, "a log and -o DIR are needed");
  r = run({"a.lcmlog", "-o", g_dir + "/z", "--frames", "7-3"});
  assert_int_equal(r.exit_status, 2);
  expect_in(r.out, "--frames must be A-B with 0 <= A <= B, not '7-3'");
  r = run({"--help"});
  assert_int_equal(r.exit_status, 0);
  expect_in(r.out, "hrdetect --frame-ids-from-names");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s HRFRAMES\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const testing_support::ScratchDir scratch("hrp_hrframes");
  if (scratch.path().empty()) return 1;
  g_dir = scratch.path();
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_frames_and_estimates_are_written),
      cmocka_unit_test(test_bad_input_is_named),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
