// hreval's report of failures (which frames fail, why, and a
// debug picture of each scenario's worst one), and a scenario file that
// cannot be read reported while the others still run.
//   argv[1]: the hreval program
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
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

using Result = testing_support::RunOutput;

Result run(const std::vector<std::string>& args) {
  return testing_support::run_capturing(g_program, args, g_dir + "/out.txt");
}

// A handrail standing in the air 2 m in front of the only wall, 0.6 and
// then 0.5 m from the camera: in reach and fully in view, and far outside
// the gap window of any surface in view, so every frame is a miss.
std::string write_unfindable_scenario() {
  const std::string path = g_dir + "/no-wall.json";
  std::ofstream(path) << R"({"name": "no-wall", "description": "a handrail far off its wall",
    "seed": 7, "frame_rate_hz": 5, "gripper_angle_deg": 90,
    "scene": {"walls": [{"center": [-2, 0, 0], "normal": [1, 0, 0], "up": [0, 0, 1],
                         "size": [8, 6], "reflectivity": 0.6}],
              "handrails": [{"kind": "iss", "foot": [0, 0, 0], "normal": [1, 0, 0],
                             "axis": [0, 1, 0], "length": 0.2}]},
    "poses": [{"label": "near", "position": [0.6, 0.0, 0.0], "rpy_deg": [0, 0, 0], "frames": 2},
              {"label": "nearer", "position": [0.5, 0.0, 0.0], "rpy_deg": [0, 0, 0],
               "frames": 2}]})";
  return path;
}

// The line of the failures table for `scenario` and `method`.
std::string failure_row(const std::string& report, const std::string& scenario,
                        const std::string& method) {
  const std::string head = "| " + scenario + " | " + method + " |";
  const std::size_t at = report.find(head, report.find("## Failures"));
  if (at == std::string::npos) return "";
  return report.substr(at, report.find('\n', at) - at);
}

// The object of column `name` in targets.json ("{...}"), empty if none.
std::string column_object(const std::string& json, const std::string& name) {
  const std::size_t at = json.find("\"" + name + "\": {");
  if (at == std::string::npos) return "";
  const std::size_t open = json.find('{', at);
  return json.substr(open, json.find('}', open) + 1 - open);
}

// Width and height from a PNG's IHDR chunk; false if it is not a PNG.
bool png_size(const std::string& bytes, unsigned* w, unsigned* h) {
  if (bytes.size() < 24 || bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return false;
  if (bytes.compare(12, 4, "IHDR") != 0) return false;
  auto be32 = [&](std::size_t k) {
    unsigned v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(bytes[k + i]);
    return v;
  };
  *w = be32(16);
  *h = be32(20);
  return true;
}

void test_the_worst_frame_is_named_with_its_reason_and_drawn(void**) {
  const std::string out = g_dir + "/worst";
  const Result r = run({"--out", out, write_unfindable_scenario()});
  assert_int_equal(r.exit_status, 0);
  const std::string report = testing_support::read_text(out + "/report.md");
  const std::string row = failure_row(report, "no-wall", "proposed");
  // All four frames missed; the worst is the first at 0.5 m (as fully in
  // view as at 0.6 m, and nearer), with the detector's reason.
  if (row.find("| 4: 0-3 |") == std::string::npos ||
      row.find("[2: missed, ") == std::string::npos ||
      row.find("](worst/no-wall.png), [lines](worst/no-wall.lines.json) |") == std::string::npos) {
    fail_msg("unexpected failures row: %s\nreport:\n%s", row.c_str(), report.c_str());
  }
  // Beside the picture, the same detection with every line it tested.
  const std::string lines = testing_support::read_text(out + "/worst/no-wall.lines.json");
  if (lines.find("{\"frame\":\"no-wall frame 2\",\"frame_id\":2,\"state\":\"NH\"") != 0 ||
      lines.find(",\"lines\":[") == std::string::npos || lines.back() != '\n') {
    fail_msg("unexpected line trace: %s", lines.c_str());
  }
  unsigned w = 0, h = 0;
  assert_true(png_size(testing_support::read_text(out + "/worst/no-wall.png"), &w, &h));
  // Seven stage pictures of 3 x 224 by 3 x 171, four to a row, 6 px apart,
  // under a two-line caption.
  assert_int_equal(w, 4 * 672 + 5 * 6);
  assert_int_equal(h, 8 + 2 * 20 + 2 * (513 + 6) + 6);
}

// For a report kept in the repository: the worst frame named with its
// reason, no picture written and no link to one.
void test_without_pictures_the_worst_frame_is_named_only(void**) {
  const std::string out = g_dir + "/no-pictures";
  const Result r = run({"--out", out, "--no-pictures", write_unfindable_scenario()});
  assert_int_equal(r.exit_status, 0);
  const std::string row =
      failure_row(testing_support::read_text(out + "/report.md"), "no-wall", "proposed");
  if (row.find("| 4: 0-3 |") == std::string::npos ||
      row.find("| 2: missed, ") == std::string::npos || row.find("worst/") != std::string::npos) {
    fail_msg("unexpected failures row: %s", row.c_str());
  }
  assert_int_not_equal(access((out + "/worst").c_str(), F_OK), 0);
}

// A frame count that is not one (it was: "abc" ran 0 frames, wrote a
// report of nan over the last one, exit 0): exit 2 naming it, and no
// report written.
void test_a_bad_frame_count_is_refused(void**) {
  const std::string out = g_dir + "/bad-count";
  for (const char* bad : {"abc", "-3", "2x", "0"}) {
    const Result r = run({"--out", out, "--max-frames", bad,
                          testing_support::source_path("sim_hal/scenarios/table2-iss.json")});
    assert_int_equal(r.exit_status, 2);
    assert_true(r.out.find(std::string("--max-frames must be a whole number")) !=
                std::string::npos);
  }
  assert_int_not_equal(access((out + "/report.md").c_str(), F_OK), 0);
}

// (Named as a newcomer would, without its folder and suffix.)
void test_a_scenario_without_failures_has_no_worst_frame(void**) {
  const std::string out = g_dir + "/clean";
  const Result r = run({"--out", out, "--max-frames", "2", "--scenarios",
                        testing_support::source_path("sim_hal/scenarios"), "table2-iss"});
  assert_int_equal(r.exit_status, 0);
  const std::string row =
      failure_row(testing_support::read_text(out + "/report.md"), "table2-iss", "proposed");
  if (row.find("| none | none |") == std::string::npos ||
      row.compare(row.size() - 5, 5, "| - |") != 0) {
    fail_msg("expected no failures and no worst frame: %s", row.c_str());
  }
  assert_int_not_equal(access((out + "/worst/table2-iss.png").c_str(), F_OK), 0);
  assert_int_not_equal(access((out + "/worst/table2-iss.lines.json").c_str(), F_OK), 0);
  // A flat wall alone: no targets table.
  assert_int_not_equal(access((out + "/targets.json").c_str(), F_OK), 0);
}

// The targets table: the rack-wall scenarios pooled, the flat wall's
// left out, the frames without a handrail counted from the one scenario
// that has them, and the same figures in targets.json. The counts checked
// come from the ground truth alone (3 frames each: the 1.04 m rail in
// reach in every frame, the rack corner with no handrail in any).
void test_the_targets_table_pools_the_rack_walls(void**) {
  const std::string out = g_dir + "/targets";
  const Result r =
      run({"--out", out, "--max-frames", "3",
           testing_support::source_path("sim_hal/scenarios/rack-table2-iss-1-04.json"),
           testing_support::source_path("sim_hal/scenarios/rack-no-handrail-corner.json"),
           write_unfindable_scenario()});
  assert_int_equal(r.exit_status, 0);
  const std::string report = testing_support::read_text(out + "/report.md");
  const std::size_t at = report.find("## Figures against the targets");
  if (at == std::string::npos ||
      report.find("| figure | rack wall | pooled | target | pooled meets it |", at) ==
          std::string::npos ||
      report.find("| frames without a handrail: a false detection | ", at) == std::string::npos) {
    fail_msg("no targets table with a rack-wall and a pooled column:\n%s", report.c_str());
  }
  const std::string json = testing_support::read_text(out + "/targets.json");
  const std::string rack = column_object(json, "rack wall");
  if (rack.find("{\"in_reach_found\": ") != 0 ||
      rack.find("\"in_reach_frames\": 3, \"no_target_frames\": 3,") == std::string::npos ||
      json.find("\"flat wall\"") != std::string::npos ||
      json.find("\"met\": {\"in_reach_found_pct\": ") == std::string::npos) {
    fail_msg("unexpected targets.json: %s", json.c_str());
  }
  // One surface: the pooled column repeats it, figure for figure.
  if (column_object(json, "pooled") != rack) {
    fail_msg("the pooled column differs from the only surface's: %s", json.c_str());
  }
}

// The held-out module's object in lomo.json ("{...}" up to its figures'
// end), empty if none.
std::string held_out_object(const std::string& json, const std::string& module) {
  const std::size_t at = json.find("\"" + module + "\": {\"chosen\"");
  if (at == std::string::npos) return "";
  return json.substr(at, json.find("}}", at) + 2 - at);
}

// Each module held out: the candidate is chosen on the other module
// alone. A configuration that finds nothing (every line needs more inliers
// than a frame has pixels) loses to the one that finds the handrails,
// whichever of them is the base configuration.
void test_leave_one_module_out_chooses_on_the_other_modules(void**) {
  const std::string blind = g_dir + "/blind.json", plain = g_dir + "/plain.json";
  std::ofstream(blind) << R"({"min_line_inliers": 100000})";
  std::ofstream(plain) << "{}";
  const std::vector<std::string> scenarios = {
      testing_support::source_path("sim_hal/scenarios/table2-iss.json"),
      testing_support::source_path("sim_hal/scenarios/rack-table2-iss-0-53.json")};
  struct Case {
    std::vector<std::string> options;
    std::string winner;
  } cases[] = {{{"--candidate", blind}, "default"},
               {{"--config", blind, "--candidate", plain}, plain}};
  for (const Case& c : cases) {
    std::vector<std::string> args = {"--out", g_dir + "/lomo", "--max-frames", "3"};
    args.insert(args.end(), c.options.begin(), c.options.end());
    args.insert(args.end(), scenarios.begin(), scenarios.end());
    const Result r = run(args);
    assert_int_equal(r.exit_status, 0);
    const std::string json = testing_support::read_text(g_dir + "/lomo/lomo.json");
    for (const char* module : {"flat wall", "rack wall"}) {
      const std::string held = held_out_object(json, module);
      if (held.find("\"chosen\": \"" + c.winner + "\"") == std::string::npos ||
          held.find("\"in_reach_found\": 3, \"in_reach_frames\": 3") == std::string::npos) {
        fail_msg("%s held out: expected %s chosen, finding all 3 in reach: %s", module,
                 c.winner.c_str(), json.c_str());
      }
    }
    const std::string report = testing_support::read_text(g_dir + "/lomo/report.md");
    // Where the figures come from: when, which commit, which machine.
    const std::size_t run = report.find("\nRun ");
    if (run == std::string::npos || report.find(" UTC, ", run) == std::string::npos ||
        report.find(" cores), ", run) == std::string::npos ||
        (report.find("commit ", run) == std::string::npos &&
         report.find("not a git checkout", run) == std::string::npos)) {
      fail_msg("the report does not say where it was run:\n%.400s", report.c_str());
    }
    if (report.find("| flat wall | `" + c.winner + "` | 100.0 |") == std::string::npos) {
      fail_msg("no held-out row for the flat wall:\n%s", report.c_str());
    }
  }
}

void test_an_unreadable_scenario_is_reported_and_the_rest_still_run(void**) {
  const std::string out = g_dir + "/partly";
  const std::string missing = g_dir + "/no-such-scenario.json";
  const Result r = run({"--out", out, missing, write_unfindable_scenario()});
  assert_int_equal(r.exit_status, 1);
  if (r.out.find(missing) == std::string::npos || r.out.find("(skipped)") == std::string::npos) {
    fail_msg("the missing file should be named and skipped:\n%s", r.out.c_str());
  }
  assert_false(
      failure_row(testing_support::read_text(out + "/report.md"), "no-wall", "proposed").empty());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s HREVAL\n", argv[0]);
    return 2;
  }
  g_program = argv[1];
  const testing_support::ScratchDir scratch("hrp_hreval");
  if (scratch.path().empty()) return 1;
  g_dir = scratch.path();
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_the_worst_frame_is_named_with_its_reason_and_drawn),
      cmocka_unit_test(test_without_pictures_the_worst_frame_is_named_only),
      cmocka_unit_test(test_a_bad_frame_count_is_refused),
      cmocka_unit_test(test_a_scenario_without_failures_has_no_worst_frame),
      cmocka_unit_test(test_the_targets_table_pools_the_rack_walls),
      cmocka_unit_test(test_leave_one_module_out_chooses_on_the_other_modules),
      cmocka_unit_test(test_an_unreadable_scenario_is_reported_and_the_rest_still_run),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
