// Whole-file reading is bounded: sizes are checked before anything is
// allocated, and only regular files are read (a FIFO would block, a device
// like /dev/zero would never end).
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "cmocka_cpp.hpp"
#include "formats/json.hpp"
#include "formats/text_file.hpp"

namespace {

std::string scratch_dir() {
  char name[] = "/tmp/hrp_text_file_XXXXXX";
  assert_non_null(mkdtemp(name));
  return name;
}

void write_file(const std::string& path, const std::string& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  assert_non_null(f);
  assert_int_equal(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
  std::fclose(f);
}

void test_reads_a_regular_file_whole(void**) {
  const std::string dir = scratch_dir();
  write_file(dir + "/a.json", "{\"k\": 1}\n");
  std::string text, error;
  assert_int_equal(
      static_cast<int>(formats::read_file_bounded(dir + "/a.json", 100, &text, &error)),
      static_cast<int>(formats::FileStatus::kOk));
  assert_string_equal(text.c_str(), "{\"k\": 1}\n");
  std::remove((dir + "/a.json").c_str());
  rmdir(dir.c_str());
}

void test_refuses_what_is_not_a_bounded_regular_file(void**) {
  const std::string dir = scratch_dir();
  const std::string fifo = dir + "/g.json";
  assert_int_equal(mkfifo(fifo.c_str(), 0600), 0);
  const std::string big = dir + "/big.json";
  write_file(big, std::string(101, ' '));
  struct Case {
    std::string path;
    formats::FileStatus status;
    const char* says;
  } cases[] = {
      {dir + "/missing.json", formats::FileStatus::kCannotOpen, "cannot open (No such file"},
      {dir, formats::FileStatus::kNotRegular, "not a regular file (a folder)"},
      {fifo, formats::FileStatus::kNotRegular, "not a regular file (a device, FIFO or socket)"},
      {"/dev/zero", formats::FileStatus::kNotRegular, "not a regular file"},
      {big, formats::FileStatus::kTooLarge, "over the limit of"},
  };
  for (const Case& c : cases) {
    std::string text = "left over", error;
    const formats::FileStatus got = formats::read_file_bounded(c.path, 100, &text, &error);
    if (got != c.status || error.rfind(c.path + ": ", 0) != 0 ||
        error.find(c.says) == std::string::npos) {
      fail_msg("%s: got %s \"%s\", expected %s \"...%s\"", c.path.c_str(), formats::to_string(got),
               error.c_str(), formats::to_string(c.status), c.says);
    }
    assert_true(text.empty());
  }
  // The JSON loader goes through the same reader: a FIFO named like a
  // configuration is refused, not waited on.
  formats::JsonValue v;
  std::string error;
  assert_false(formats::load_json_file(fifo, &v, &error));
  assert_non_null(std::strstr(error.c_str(), "not a regular file"));
  std::remove(fifo.c_str());
  std::remove(big.c_str());
  rmdir(dir.c_str());
}

void test_json_file_errors_name_path_and_line(void**) {
  const std::string dir = scratch_dir();
  const std::string path = dir + "/c.json";
  write_file(path, "{\n \"a\": 1,\n \"a\": 2\n}\n");
  formats::JsonValue v;
  std::string error;
  assert_false(formats::load_json_file(path, &v, &error));
  assert_string_equal(error.c_str(), (path + ":3: duplicate key \"a\"").c_str());
  std::remove(path.c_str());
  rmdir(dir.c_str());
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_reads_a_regular_file_whole),
      cmocka_unit_test(test_refuses_what_is_not_a_bounded_regular_file),
      cmocka_unit_test(test_json_file_errors_name_path_and_line),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
