// hrdetect against the inputs testing from outside found it mishandled,
// each now with a clear error naming the file and the good files still
// processed: /dev/zero (it grew to 2.1 GB), a FIFO named g.pcd in a folder
// (it hung), a 141-byte header claiming 8192 x 8192 points (1.3 GB), a
// folder named x.pcd, an empty folder and an unwritable stdout or
// --debug-png folder (exit 0 before; a --debug-png path that is a file is
// refused up front).
//   argv[1]: the hrdetect program
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "cmocka_cpp.hpp"
#include "test_data.hpp"

namespace {

std::string g_program;
std::string g_dir;

struct Result {
  int exit_status = -1;
  std::string out;  // stdout and stderr together
  int json_lines = 0;
};

Result run(const std::vector<std::string>& args, const std::string& stdout_path = "") {
  const std::string log = g_dir + "/out.txt";
  Result r;
  if (stdout_path.empty()) {
    r.exit_status =
        testing_support::wait_for_exit(testing_support::spawn_program(g_program, args, log));
  } else {
    // stdout to stdout_path, stderr to the log.
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, stdout_path.c_str(), O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<std::string> all = args;
    all.insert(all.begin(), g_program);
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    assert_int_equal(posix_spawn(&pid, g_program.c_str(), &actions, nullptr, argv.data(), environ),
                     0);
    posix_spawn_file_actions_destroy(&actions);
    r.exit_status = testing_support::wait_for_exit(pid);
  }
  std::ifstream in(log);
  std::stringstream ss;
  ss << in.rdbuf();
  r.out = ss.str();
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);)
    r.json_lines += line.rfind("{\"frame\"", 0) == 0;
  return r;
}

void expect_in(const Result& r, const std::string& text) {
  if (r.out.find(text) == std::string::npos) {
    fail_msg("expected \"%s\" in hrdetect's output:\n%s", text.c_str(), r.out.c_str());
  }
}

const std::string kGood = testing_support::source_path("tests/data/table2-iss-1.pcd");

void test_a_device_is_refused_and_the_next_file_processed(void**) {
  const Result r = run({"/dev/zero", kGood});
  assert_int_equal(r.exit_status, 1);
  expect_in(r, "/dev/zero: not a regular file");
  assert_int_equal(r.json_lines, 1);
}

void test_a_fifo_and_a_folder_named_pcd_are_refused_not_waited_on(void**) {
  const std::string folder = g_dir + "/frames";
  mkdir(folder.c_str(), 0755);
  assert_int_equal(mkfifo((folder + "/g.pcd").c_str(), 0600), 0);
  mkdir((folder + "/x.pcd").c_str(), 0755);
  assert_int_equal(symlink(kGood.c_str(), (folder + "/a.pcd").c_str()), 0);
  const Result r = run({folder});
  assert_int_equal(r.exit_status, 1);
  expect_in(r, "g.pcd: not a regular file (a device, FIFO or socket)");
  expect_in(r, "x.pcd: not a regular file (a folder)");
  assert_int_equal(r.json_lines, 1);
}

void test_a_header_claiming_a_huge_frame_is_refused_before_allocating(void**) {
  const std::string path = g_dir + "/huge.pcd";
  std::FILE* f = std::fopen(path.c_str(), "w");
  std::fputs(
      "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 8192\nHEIGHT "
      "8192\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 67108864\nDATA binary\n",
      f);
  std::fclose(f);
  const Result r = run({path, kGood});
  assert_int_equal(r.exit_status, 1);
  expect_in(r, "huge.pcd: WIDTH x HEIGHT 8192 x 8192");
  expect_in(r, "over the limit of");
  assert_int_equal(r.json_lines, 1);
}

void test_an_empty_folder_is_an_error(void**) {
  const std::string empty = g_dir + "/empty";
  mkdir(empty.c_str(), 0755);
  const Result r = run({empty});
  assert_int_equal(r.exit_status, 1);
  expect_in(r, "no .pcd files in this folder");
}

void test_results_that_cannot_be_written_are_an_error(void**) {
  Result r = run({kGood}, "/dev/full");
  assert_int_equal(r.exit_status, 1);
  expect_in(r, "cannot write the results to stdout");
  // /dev/full is no folder and cannot be made one: refused, named, before
  // any frame is read (a bad option, exit 2).
  r = run({"--debug-png", "/dev/full", kGood});
  assert_int_equal(r.exit_status, 2);
  expect_in(r, "--debug-png: cannot create /dev/full");
  assert_int_equal(r.json_lines, 0);
  // A folder in which the picture cannot be written (its name taken by a
  // folder): that frame's picture fails and is reported, its result is
  // still written.
  const std::string pictures = g_dir + "/pictures";
  assert_int_equal(mkdir(pictures.c_str(), 0755), 0);
  assert_int_equal(mkdir((pictures + "/table2-iss-1_g_pose.png").c_str(), 0755), 0);
  r = run({"--debug-png", pictures, kGood});
  assert_int_equal(r.exit_status, 1);
  expect_in(r, "--debug-png:");
  expect_in(r, "table2-iss-1_g_pose.png");
  assert_int_equal(r.json_lines, 1);
}

// --mounts adds the dominant plane (a wall 0.6 m away) and the surfaces
// measured from it to each line, which still ends as one JSON object.
void test_mounts_are_reported_when_asked(void**) {
  Result r = run({kGood});
  assert_int_equal(r.exit_status, 0);
  assert_true(r.out.find("mount_search") == std::string::npos);
  r = run({"--mounts", kGood});
  assert_int_equal(r.exit_status, 0);
  assert_int_equal(r.json_lines, 1);
  expect_in(r, ",\"mount_search\":{\"plane\":{\"normal\":[");
  expect_in(r, "\"d_m\":0.");
  expect_in(r, "\"surfaces_m\":[");
  expect_in(r, "\"plane_front_pixels\":");
  expect_in(r, ",\"front_peak_mounts\":");
  assert_true(r.out.find("}}\n") != std::string::npos);
}

// --lines: every line the detector tested on the frame, in order, with its
// verdict; on the good frame (a bar on a wall) the accepted one carries its
// place, its mount and both ends seen. Without the option, no such array.
void test_lines_are_reported_when_asked(void**) {
  Result r = run({kGood});
  assert_int_equal(r.exit_status, 0);
  assert_true(r.out.find("\"lines\"") == std::string::npos);
  r = run({"--lines", kGood});
  assert_int_equal(r.exit_status, 0);
  assert_int_equal(r.json_lines, 1);
  expect_in(r, ",\"lines\":[{\"search\":0,\"search_mount_m\":");
  expect_in(r, "\"verdict\":\"ACCEPTED\",\"inliers\":");
  expect_in(r, "\"front_m\":0.0");
  expect_in(r, "\"mount_m\":");
  expect_in(r, "\"ends_seen\":[true,true]}");
  assert_true(r.out.find("lines_not_kept") == std::string::npos);
  assert_true(r.out.find("]}\n") != std::string::npos);
}

// A frame's id seeds the detector's random stream. By default the files
// are numbered in order; --frame-ids-from-names takes the id a recorded
// run's frame had (hrframes' frame_NNNNN.pcd), so that the flight's answer
// is reproduced. A name that ends in no digits is refused by name and the
// other files are still processed.
void test_frame_ids_from_names(void**) {
  const std::string named = g_dir + "/frame_00042.pcd", plain = g_dir + "/wall.pcd";
  for (const std::string& copy : {named, plain}) {
    std::ifstream in(kGood, std::ios::binary);
    std::ofstream out(copy, std::ios::binary);
    out << in.rdbuf();
  }
  Result r = run({named, plain});
  assert_int_equal(r.exit_status, 0);
  expect_in(r, "frame_00042.pcd\",\"frame_id\":0,");
  expect_in(r, "wall.pcd\",\"frame_id\":1,");
  r = run({"--frame-ids-from-names", plain, named});
  assert_int_equal(r.exit_status, 1);
  assert_int_equal(r.json_lines, 1);
  expect_in(r, "frame_00042.pcd\",\"frame_id\":42,");
  expect_in(r, "wall.pcd: --frame-ids-from-names: the name ends in no frame id");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s HRDETECT\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const testing_support::ScratchDir scratch("hrp_hrdetect");
  if (scratch.path().empty()) return 1;
  g_dir = scratch.path();
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_a_device_is_refused_and_the_next_file_processed),
      cmocka_unit_test(test_a_fifo_and_a_folder_named_pcd_are_refused_not_waited_on),
      cmocka_unit_test(test_a_header_claiming_a_huge_frame_is_refused_before_allocating),
      cmocka_unit_test(test_an_empty_folder_is_an_error),
      cmocka_unit_test(test_results_that_cannot_be_written_are_an_error),
      cmocka_unit_test(test_mounts_are_reported_when_asked),
      cmocka_unit_test(test_frame_ids_from_names),
      cmocka_unit_test(test_lines_are_reported_when_asked),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
