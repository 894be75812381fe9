// hrdetect: runs the handrail detector on organized PCD files and prints one
// JSON object per frame. See tools/README.md.
#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "common/detection_json.hpp"
#include "common/frame_convert.hpp"
#include "common/output_dir.hpp"
#include "common/stage_pictures.hpp"
#include "estimator/config_io.hpp"
#include "estimator/handrail_detector.hpp"
#include "estimator/handrail_tracker.hpp"
#include "formats/pcd_io.hpp"

namespace {

void usage(FILE* out) {
  std::fprintf(out,
               "usage: hrdetect [options] PATH...\n"
               "Detects the handrail in organized PCD files (or folders of them, taken in\n"
               "name order) and prints one JSON object per frame on stdout. PCD data may be\n"
               "ascii, binary or binary_compressed (PCL's LZF form).\n\n"
               "options:\n"
               "  --method proposed|basic  the paper's detector (default) or its basic baseline\n"
               "  --gripper-angle DEG      angle of handrails the gripper takes; 0 (default) =\n"
               "                           handrails along the image's y axis\n"
               "  --handrail iss|round     handrail geometry (default iss; see --config)\n"
               "  --config FILE            detector configuration (JSON; estimator/doc/config.md)\n"
               "  --debug-png DIR          pictures of each stage per frame (DIR/NAME_STAGE.png)\n"
               "  --sequence               the files are a time series from a still camera, in\n"
               "                           the given order: track the handrail over them (the\n"
               "                           paper's Tr1..Tr3 and an outlier gate) and add a\n"
               "                           \"track\" object to each line\n"
               "  --frame-ids-from-names   each file's frame id (the detector's random stream)\n"
               "                           from the digits that end its name, frame_00042.pcd\n"
               "                           is 42, as hrframes names a recorded run's frames:\n"
               "                           the flight estimator's answer on the same frame;\n"
               "                           without it the files are numbered 0, 1, ... in order\n"
               "  --mounts                 add a \"mount_search\" object to each line: the\n"
               "                           surfaces in view and the mounts searched, as\n"
               "                           distances from the dominant plane (tools/README.md)\n"
               "  --lines                  add a \"lines\" array to each line: every line the\n"
               "                           detector put to its tests, in order, with its\n"
               "                           verdict, mount search, place and ends\n"
               "                           (tools/README.md): why the line that won won\n"
               "  -h, --help               this text\n\n"
               "Every line also has \"best_line\": the line with the most inliers over all\n"
               "of the frame's mount searches, with the search that tested it, its mount,\n"
               "place and verdict (null when no line was tested): why the bar, when it was\n"
               "in view, was refused. --debug-png draws it, with its verdict, if refused.\n\n"
               "exit status: 0 when every file was read, 1 when any file could not be\n"
               "(the others are still processed), 2 for bad options.\n");
}

bool is_dir(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool ends_with(const std::string& s, const char* suffix) {
  const std::size_t n = std::strlen(suffix);
  return s.size() >= n && s.compare(s.size() - n, n, suffix) == 0;
}

// Files named on the command line, with folders expanded to their .pcd files.
bool collect_inputs(const std::vector<std::string>& args, std::vector<std::string>* files) {
  bool ok = true;
  for (const std::string& a : args) {
    if (!is_dir(a)) {
      files->push_back(a);
      continue;
    }
    DIR* d = opendir(a.c_str());
    if (!d) {
      std::fprintf(stderr, "hrdetect: %s: cannot read folder: %s\n", a.c_str(),
                   std::strerror(errno));
      ok = false;
      continue;
    }
    std::vector<std::string> found;
    while (dirent* e = readdir(d)) {
      const std::string name = e->d_name;
      if (ends_with(name, ".pcd")) found.push_back(a + "/" + name);
    }
    closedir(d);
    std::sort(found.begin(), found.end());
    if (found.empty()) {
      std::fprintf(stderr, "hrdetect: %s: no .pcd files in this folder\n", a.c_str());
      ok = false;
    }
    files->insert(files->end(), found.begin(), found.end());
  }
  return ok;
}

std::string stem(const std::string& path) {
  std::string s = path.substr(path.find_last_of('/') + 1);
  if (ends_with(s, ".pcd")) s.resize(s.size() - 4);
  return s;
}

// The frame id a file's name ends with (frame_00042.pcd: 42); false when
// the name ends in no digits.
bool frame_id_from_name(const std::string& path, std::uint64_t* id) {
  const std::string s = stem(path);
  std::size_t start = s.size();
  while (start > 0 && std::isdigit(static_cast<unsigned char>(s[start - 1]))) --start;
  if (start == s.size() || s.size() - start > 18) return false;
  std::uint64_t value = 0;
  for (std::size_t k = start; k < s.size(); ++k) value = 10 * value + (s[k] - '0');
  *id = value;
  return true;
}

// `object` (one JSON object) with "name": value added at its end.
void append_field(std::string* object, const char* name, const std::string& value) {
  object->pop_back();  // the closing brace
  *object += ",\"" + std::string(name) + "\":" + value + "}";
}

// The lines the detector tested on this frame. A frame it turned away
// before sampling it (empty, too large) leaves the last frame's trace in
// place: none of those lines are this frame's.
const estimator::LineTrace& frame_line_trace(const estimator::HandrailDetector& det,
                                             const estimator::HandrailDetection& d) {
  static const estimator::LineTrace kNoLines;
  const bool sampled = d.status != estimator::DetectStatus::kEmptyFrame &&
                       d.status != estimator::DetectStatus::kFrameTooLarge;
  return sampled ? det.last_line_trace() : kNoLines;
}

// The best-supported line when the detector refused it (null otherwise):
// the one the pictures must show, since the workspace shows only one
// search, and an accepted line is the pose already drawn.
const estimator::LineTraceEntry* refused(const estimator::LineTraceEntry* best) {
  return best && best->verdict != estimator::LineVerdict::kAccepted ? best : nullptr;
}

// One picture per stage (common/stage_pictures.hpp), each written to
// DIR/NAME_STAGE.png, with the refused line (or none) drawn over the line
// and pose pictures. False, with *error, when a picture could not be
// written; the others are still written.
bool write_debug_pictures(const std::string& dir, const std::string& name,
                          const hal::DepthFrame& frame, const estimator::OrganizedCloud& cloud,
                          const estimator::HandrailDetector& det,
                          const estimator::HandrailDetection& d,
                          const estimator::LineTraceEntry* refused_line, std::string* error) {
  bool written = true;
  for (const tools::StagePicture& p :
       tools::draw_stage_pictures(frame, cloud, det, d, {}, refused_line)) {
    written = p.image.write_png(dir + "/" + name + "_" + p.suffix + ".png", error) && written;
  }
  return written;
}

}  // namespace

int main(int argc, char** argv) {
  estimator::DetectorConfig cfg;
  estimator::Method method = estimator::Method::kProposed;
  std::string config_path, debug_dir, handrail = "iss";
  double gripper_deg = 0.0;
  bool gripper_given = false, sequence = false, show_mounts = false, ids_from_names = false;
  bool show_lines = false;
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&](const char* what) -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "hrdetect: %s needs a value (see --help)\n", what);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--method") {
      const std::string m = next("--method");
      if (m == "proposed")
        method = estimator::Method::kProposed;
      else if (m == "basic")
        method = estimator::Method::kBasic;
      else {
        std::fprintf(stderr, "hrdetect: --method must be proposed or basic, not '%s'\n", m.c_str());
        return 2;
      }
    } else if (a == "--gripper-angle") {
      const std::string v = next("--gripper-angle");
      char* end = nullptr;
      gripper_deg = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || gripper_deg < 0.0 || gripper_deg > 90.0) {
        std::fprintf(stderr, "hrdetect: --gripper-angle takes degrees in 0..90, not '%s'\n",
                     v.c_str());
        return 2;
      }
      gripper_given = true;
    } else if (a == "--handrail") {
      handrail = next("--handrail");
      if (handrail != "iss" && handrail != "round") {
        std::fprintf(stderr, "hrdetect: --handrail must be iss or round, not '%s'\n",
                     handrail.c_str());
        return 2;
      }
    } else if (a == "--config") {
      config_path = next("--config");
    } else if (a == "--sequence") {
      sequence = true;
    } else if (a == "--mounts") {
      show_mounts = true;
    } else if (a == "--lines") {
      show_lines = true;
    } else if (a == "--frame-ids-from-names") {
      ids_from_names = true;
    } else if (a == "--debug-png") {
      debug_dir = next("--debug-png");
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "hrdetect: unknown option '%s' (see --help)\n", a.c_str());
      return 2;
    } else {
      args.push_back(a);
    }
  }
  if (args.empty()) {
    usage(stderr);
    return 2;
  }
  if (handrail == "round")
    cfg.handrail = estimator::paper_round_handrail(cfg.handrail.bar_length_m);
  std::string error;
  if (!config_path.empty() && !estimator::load_detector_config(config_path, &cfg, &error)) {
    std::fprintf(stderr, "hrdetect: %s\n", error.c_str());
    return 2;
  }
  if (gripper_given) cfg.gripper_angle_rad = static_cast<float>(gripper_deg * M_PI / 180.0);
  if (!debug_dir.empty() && !tools::make_output_dir(debug_dir, &error)) {
    std::fprintf(stderr, "hrdetect: --debug-png: %s\n", error.c_str());
    return 2;
  }

  std::vector<std::string> files;
  bool all_read = collect_inputs(args, &files);
  // The pictures show the workspace: keep it on the winning mount's search.
  if (!debug_dir.empty()) cfg.workspace_shows_result = true;
  estimator::HandrailDetector detector(cfg);
  // Always on: every line reports its best-supported line. The trace is a
  // fixed buffer in the detector, one copy per tested line.
  detector.set_line_trace(true);
  estimator::TrackerConfig track_cfg;
  track_cfg.target_standoff_m = cfg.target_standoff_m;
  estimator::HandrailTracker tracker(track_cfg);
  const Eigen::Isometry3f still = Eigen::Isometry3f::Identity();
  std::vector<estimator::CloudPoint> buffer;
  formats::PcdFrame pcd;
  std::uint64_t frame_id = 0;
  for (const std::string& file : files) {
    // Limited to the detector's largest frame before anything is allocated.
    if (!formats::read_pcd(file, &pcd, &error,
                           static_cast<std::uint64_t>(cfg.max_width) * cfg.max_height)) {
      std::fprintf(stderr, "hrdetect: %s\n", error.c_str());
      all_read = false;
      continue;
    }
    if (pcd.width > cfg.max_width || pcd.height > cfg.max_height) {
      std::fprintf(stderr,
                   "hrdetect: %s: frame %ux%u is larger than the configured maximum %ux%u "
                   "(max_width/max_height)\n",
                   file.c_str(), pcd.width, pcd.height, cfg.max_width, cfg.max_height);
      all_read = false;
      continue;
    }
    std::uint64_t id = frame_id++;
    if (ids_from_names && !frame_id_from_name(file, &id)) {
      std::fprintf(stderr,
                   "hrdetect: %s: --frame-ids-from-names: the name ends in no frame id "
                   "(as frame_00042.pcd); skipped\n",
                   file.c_str());
      all_read = false;
      continue;
    }
    const hal::DepthFrame frame = pcd.view(id, 0);
    const estimator::OrganizedCloud cloud = tools::to_estimator_cloud(frame, &buffer);
    const estimator::HandrailDetection d = detector.detect(cloud, method);
    const estimator::LineTrace& trace = frame_line_trace(detector, d);
    const estimator::LineTraceEntry* best = tools::best_supported_line(trace);
    std::string line = tools::detection_to_json(file, d);
    append_field(&line, "best_line", tools::best_line_to_json(best));
    if (show_mounts) {
      append_field(&line, "mount_search",
                   tools::mounts_to_json(detector.last_dominant_plane(), detector.last_mounts()));
    }
    if (show_lines) line = tools::with_line_trace(line, trace);
    if (sequence)
      append_field(&line, "track", tools::track_to_json(tracker.update(d, still, still)));
    // A result that cannot be written is lost: say so and stop, since
    // every later one would be lost too.
    if (std::printf("%s\n", line.c_str()) < 0 || std::fflush(stdout) != 0) {
      std::fprintf(stderr, "hrdetect: cannot write the results to stdout: %s\n",
                   std::strerror(errno));
      return 1;
    }
    if (!debug_dir.empty() && !write_debug_pictures(debug_dir, stem(file), frame, cloud, detector,
                                                    d, refused(best), &error)) {
      std::fprintf(stderr, "hrdetect: --debug-png: %s\n", error.c_str());
      all_read = false;
    }
  }
  return all_read ? 0 : 1;
}
