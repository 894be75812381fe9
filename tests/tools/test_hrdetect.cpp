// hrdetect against the inputs testing from outside found it mishandled,
// each now with a clear error naming the file and the good files still
// processed: /dev/zero (it grew to 2.1 GB), a FIFO named g.pcd in a folder
// (it hung), a 141-byte header claiming 8192 x 8192 points (1.3 GB), a
// folder named x.pcd, an empty folder and an unwritable stdout or
// --debug-png folder (exit 0 before; a --debug-png path that is a file is
// refused up front). Then what each line reports: the mounts, the line
// trace, and the best-supported line of all searches (best_line), in the
// JSON and drawn in the debug pictures.
//   argv[1]: the hrdetect program
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <png.h>

#include "child_process.hpp"
#include "cmocka_cpp.hpp"
#include "formats/json.hpp"
#include "stage_pictures.hpp"
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

// The frame-th JSON line of hrdetect's output, parsed.
formats::JsonValue frame_json(const Result& r, int frame) {
  std::istringstream lines(r.out);
  int k = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("{\"frame\"", 0) != 0 || k++ != frame) continue;
    formats::JsonValue v;
    std::string error;
    if (!formats::parse_json(line, &v, &error)) fail_msg("%s in: %s", error.c_str(), line.c_str());
    return v;
  }
  fail_msg("no JSON line %d in hrdetect's output:\n%s", frame, r.out.c_str());
  return {};
}

std::string text_of(const formats::JsonValue& object, const char* key) {
  const formats::JsonValue* v = object.find(key);
  if (!v || !v->is_string()) fail_msg("no string \"%s\"", key);
  return v->text;
}

double number_of(const formats::JsonValue& object, const char* key) {
  const formats::JsonValue* v = object.find(key);
  if (!v || !v->is_number()) fail_msg("no number \"%s\"", key);
  return v->number;
}

// Pixels of exactly `colour` in a PNG file; -1 when it cannot be read.
long pixels_of_colour(const std::string& path, tools::Rgb colour) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return -1;
  image.format = PNG_FORMAT_RGB;
  std::vector<png_byte> rgb(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, rgb.data(), 0, nullptr)) return -1;
  long n = 0;
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3) {
    n += rgb[i] == colour.r && rgb[i + 1] == colour.g && rgb[i + 2] == colour.b;
  }
  return n;
}

// A round bar read as an ISS one (the default): the first search's first
// line was refused as CROSSES_BAR, which is all "first_line" says, yet the
// bar itself was refused as WRONG_HEIGHT by the second search (search 1),
// with 2,396 inliers. best_line names that refusal: the line of most
// inliers in the whole trace (--lines), whatever search it came from.
const std::string kRefusedLater = testing_support::source_path("tests/data/table2-round-2.pcd");

void test_best_line_names_the_refusal_of_a_later_search(void**) {
  const Result r = run({"--lines", kRefusedLater});
  assert_int_equal(r.exit_status, 0);
  const formats::JsonValue frame = frame_json(r, 0);
  assert_string_equal(text_of(frame, "reason").c_str(), "NO_LINE");
  assert_string_equal(text_of(frame, "first_line").c_str(), "CROSSES_BAR");
  const formats::JsonValue* best = frame.find("best_line");
  assert_non_null(best);
  assert_true(best->is_object());
  assert_int_equal(static_cast<int>(number_of(*best, "search")), 1);
  assert_string_equal(text_of(*best, "verdict").c_str(), "WRONG_HEIGHT");
  // The same line as the trace's best, searched on a mount off the plane.
  const formats::JsonValue* lines = frame.find("lines");
  assert_non_null(lines);
  const formats::JsonValue* most = nullptr;
  for (const formats::JsonValue& e : lines->items) {
    if (!most || number_of(e, "inliers") > number_of(*most, "inliers")) most = &e;
  }
  assert_non_null(most);
  assert_true(number_of(*best, "inliers") == number_of(*most, "inliers"));
  assert_true(number_of(*best, "search") == number_of(*most, "search"));
  assert_true(number_of(*best, "mount_m") > 0.005);
  assert_true(number_of(*best, "visible_length_m") > 0.4);  // the whole bar
  for (const char* key : {"middle_cam", "axis_cam"}) {
    const formats::JsonValue* v = best->find(key);
    assert_true(v && v->is_array() && v->items.size() == 3);
  }
  expect_in(run({"--help"}), "\"best_line\"");
}

// A frame with a find still names its best-supported line, accepted or
// not: here the found bar, seen again by the second search on another
// mount, where its front stands at the wrong height with more inliers.
// No line of the frame has more inliers than the one it accepted.
void test_a_found_frame_still_reports_its_best_line(void**) {
  const Result r = run({kGood});
  assert_int_equal(r.exit_status, 0);
  const formats::JsonValue frame = frame_json(r, 0);
  assert_string_equal(text_of(frame, "state").c_str(), "BE");
  const formats::JsonValue* best = frame.find("best_line");
  assert_true(best && best->is_object());
  assert_true(number_of(*best, "inliers") >= number_of(frame, "inliers"));
  assert_string_equal(text_of(*best, "verdict").c_str(), "WRONG_HEIGHT");
  assert_int_equal(static_cast<int>(number_of(*best, "search")), 1);
}

// --debug-png draws the refused best line in its own colour over the line
// and pose pictures; a frame whose best line was accepted gets none (its
// pose is the line).
void test_debug_pictures_draw_the_refused_best_line(void**) {
  const std::string dir = g_dir + "/best";
  const std::string accepted =
      testing_support::source_path("tests/data/overhead-module-rail-raw-75.pcd");
  const Result r = run({"--debug-png", dir, kRefusedLater, accepted});
  assert_int_equal(r.exit_status, 0);
  assert_string_equal(text_of(*frame_json(r, 1).find("best_line"), "verdict").c_str(), "ACCEPTED");
  for (const char* stage : {"f_line", "g_pose"}) {
    const long drawn =
        pixels_of_colour(dir + "/table2-round-2_" + stage + ".png", tools::kRefusedLineColour);
    if (drawn < 300) fail_msg("%s: %ld pixels of the refused line's colour", stage, drawn);
    assert_int_equal(pixels_of_colour(dir + "/overhead-module-rail-raw-75_" + stage + ".png",
                                      tools::kRefusedLineColour),
                     0);
  }
}

// A flat wall and nothing on it: no line to test, "best_line" is null
// (not the line of the frame before it), and no line is drawn.
void test_a_frame_without_lines_has_a_null_best_line(void**) {
  const std::string wall = g_dir + "/flat-wall.pcd";
  {
    std::ofstream out(wall);
    const int w = 160, h = 120;
    const double f_px = 150.0, z_m = 0.6;
    out << "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << w
        << "\nHEIGHT " << h << "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << w * h << "\nDATA ascii\n";
    for (int r = 0; r < h; ++r)
      for (int c = 0; c < w; ++c)
        out << (c - 79.5) / f_px * z_m << " " << (r - 59.5) / f_px * z_m << " " << z_m << "\n";
  }
  const std::string dir = g_dir + "/wall";
  const Result r = run({"--debug-png", dir, kRefusedLater, wall});
  assert_int_equal(r.exit_status, 0);
  assert_true(frame_json(r, 0).find("best_line")->is_object());
  const formats::JsonValue frame = frame_json(r, 1);
  assert_string_equal(text_of(frame, "reason").c_str(), "NO_CANDIDATES");
  const formats::JsonValue* best = frame.find("best_line");
  assert_non_null(best);
  assert_int_equal(static_cast<int>(best->type), static_cast<int>(formats::JsonValue::Type::kNull));
  assert_int_equal(pixels_of_colour(dir + "/flat-wall_g_pose.png", tools::kRefusedLineColour), 0);
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
      cmocka_unit_test(test_best_line_names_the_refusal_of_a_later_search),
      cmocka_unit_test(test_a_found_frame_still_reports_its_best_line),
      cmocka_unit_test(test_debug_pictures_draw_the_refused_best_line),
      cmocka_unit_test(test_a_frame_without_lines_has_a_null_best_line),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
