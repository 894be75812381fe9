// hrframes: the depth frames of a recorded run, as files the bench tools
// read. A run recorded with `fsw_app --publish-frames --log LOG` holds every
// depth frame the estimator saw (DEPTH_FRAME) and what it made of each
// (HANDRAIL_ESTIMATE). hrframes writes the frames as organized PCD files
// named by the camera's frame id, and the flight estimates beside them, so
// that `hrdetect --frame-ids-from-names` can run the same detector on the
// same frames with the same random stream and show every stage of a frame
// the run got wrong (a HIL run's divergence was found this way).
#include <lcm/lcm-cpp.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "common/output_dir.hpp"
#include "formats/pcd_io.hpp"
#include "fsw_app/depth_frame_msg.hpp"
#include "hrp/depth_frame_t.hpp"
#include "hrp/handrail_estimate_t.hpp"

namespace {

const char* const kFrameChannel = "DEPTH_FRAME";
const char* const kEstimateChannel = "HANDRAIL_ESTIMATE";
// The largest frame written: the Pico Flexx's full resolution with room to
// spare; a larger count in a message is a corrupt one.
constexpr std::size_t kMaxPoints = 640u * 480u;

void usage(FILE* out) {
  std::fprintf(out,
               "usage: hrframes LOG -o DIR [options]\n"
               "Writes the depth frames of an LCM log (recorded with fsw_app --publish-frames\n"
               "--log LOG) as DIR/frame_NNNNN.pcd, NNNNN the camera's frame id, and what the\n"
               "run's estimator reported for each frame as DIR/estimates.jsonl (one JSON\n"
               "object per %s message: frame_id, state, detect_status, bar_length_m, inliers,\n"
               "position and axis of the handrail in the camera frame). Run the same\n"
               "detector on the same frames, with the same random stream per frame, with\n"
               "  hrdetect --frame-ids-from-names [--handrail round] [--debug-png PICS] DIR\n\n"
               "options:\n"
               "  -o, --out DIR     output folder (created, with its parents, if missing)\n"
               "  --frames A-B      only frame ids A to B (inclusive)\n"
               "  --pcd-format ascii|binary|binary_compressed\n"
               "                    PCD data encoding (default binary)\n"
               "  -h, --help        this text\n\n"
               "exit status: 0 when every frame was written, 1 when the log holds no frame\n"
               "or a message did not decode or a file could not be written (named on\n"
               "stderr; the others are still written), 2 for bad options or a log that\n"
               "cannot be read.\n",
               kEstimateChannel);
}

struct Options {
  std::string log, out;
  long first = 0, last = -1;  // last < 0: no upper limit
  formats::PcdEncoding encoding = formats::PcdEncoding::kBinary;
};

bool parse_range(const std::string& text, long* first, long* last) {
  char* end = nullptr;
  *first = std::strtol(text.c_str(), &end, 10);
  if (end == text.c_str() || *end != '-' || *first < 0) return false;
  const char* second = end + 1;
  *last = std::strtol(second, &end, 10);
  return end != second && *end == '\0' && *last >= *first;
}

// 0: run; 1: help shown; 2: bad usage (reported).
int parse_options(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "hrframes: %s needs a value (see --help)\n", name);
        return nullptr;
      }
      return argv[++i];
    };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 1;
    } else if (a == "-o" || a == "--out") {
      const char* v = value("--out");
      if (!v) return 2;
      o->out = v;
    } else if (a == "--frames") {
      const char* v = value("--frames");
      if (!v) return 2;
      if (!parse_range(v, &o->first, &o->last)) {
        std::fprintf(stderr, "hrframes: --frames must be A-B with 0 <= A <= B, not '%s'\n", v);
        return 2;
      }
    } else if (a == "--pcd-format") {
      const char* v = value("--pcd-format");
      if (!v) return 2;
      const std::string f = v;
      if (f == "ascii") {
        o->encoding = formats::PcdEncoding::kAscii;
      } else if (f == "binary") {
        o->encoding = formats::PcdEncoding::kBinary;
      } else if (f == "binary_compressed") {
        o->encoding = formats::PcdEncoding::kBinaryCompressed;
      } else {
        std::fprintf(stderr,
                     "hrframes: --pcd-format must be ascii, binary or binary_compressed, not "
                     "'%s'\n",
                     v);
        return 2;
      }
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "hrframes: unknown option '%s' (see --help)\n", a.c_str());
      return 2;
    } else if (o->log.empty()) {
      o->log = a;
    } else {
      std::fprintf(stderr, "hrframes: one log only; '%s' is a second\n", a.c_str());
      return 2;
    }
  }
  if (o->log.empty() || o->out.empty()) {
    std::fprintf(stderr, "hrframes: a log and -o DIR are needed (see --help)\n");
    return 2;
  }
  return 0;
}

bool in_range(const Options& o, long frame_id) {
  return frame_id >= o.first && (o.last < 0 || frame_id <= o.last);
}

const char* state_name(int state) {
  static const char* const kNames[] = {"NH", "BE", "OE", "NE"};
  return state >= 0 && state < 4 ? kNames[state] : "?";
}

// What %.5f prints as zero is written as 0, not -0.
double tidy(double v) {
  return std::fabs(v) < 5e-6 ? 0.0 : v;
}

// One estimate as a JSON line. The handrail frame's x is the wall normal
// and its z runs along the bar (handrail_estimate_t.lcm), so the axis is
// the third column of its rotation.
std::string estimate_to_json(const hrp::handrail_estimate_t& m) {
  const double* q = m.T_cam_handrail.quat_wxyz;
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double axis[3] = {2.0 * (x * z + w * y), 2.0 * (y * z - w * x),
                          1.0 - 2.0 * (x * x + y * y)};
  const double* p = m.T_cam_handrail.position_m;
  char line[512];
  std::snprintf(line, sizeof line,
                "{\"frame_id\":%lld,\"state\":\"%s\",\"detect_status\":%d,"
                "\"bar_length_m\":%.4f,\"inliers\":%d,\"position\":[%.5f,%.5f,%.5f],"
                "\"axis\":[%.5f,%.5f,%.5f],\"num_ends\":%d}",
                static_cast<long long>(m.frame_id), state_name(m.state),
                static_cast<int>(m.detect_status), m.bar_length_m, static_cast<int>(m.inliers),
                tidy(p[0]), tidy(p[1]), tidy(p[2]), tidy(axis[0]), tidy(axis[1]), tidy(axis[2]),
                static_cast<int>(m.num_ends));
  return line;
}

struct Counts {
  long frames = 0, written = 0, failed = 0, estimates = 0, bad_estimates = 0, skipped = 0;
};

bool write_frame(const Options& o, const lcm::LogEvent& e, hrp::depth_frame_t* msg,
                 std::vector<hal::DepthPoint>* points, Counts* c) {
  const fsw_app::FrameMsgStatus st =
      fsw_app::decode_depth_frame(e.data, static_cast<std::size_t>(e.datalen), kMaxPoints, msg);
  if (st != fsw_app::FrameMsgStatus::kOk) {
    std::fprintf(stderr, "hrframes: %s: event %lld (%s) does not decode: %s; skipped\n",
                 o.log.c_str(), static_cast<long long>(e.eventnum), kFrameChannel,
                 fsw_app::to_string(st));
    return false;
  }
  if (!in_range(o, static_cast<long>(msg->frame_id))) {
    ++c->skipped;
    return true;
  }
  hal::DepthFrame frame;
  fsw_app::from_msg(*msg, points->data(), &frame);
  char name[64];
  std::snprintf(name, sizeof name, "/frame_%05lld.pcd", static_cast<long long>(msg->frame_id));
  std::string error;
  if (!formats::write_pcd(o.out + name, frame, o.encoding, &error)) {
    std::fprintf(stderr, "hrframes: %s\n", error.c_str());
    return false;
  }
  ++c->written;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  const int parsed = parse_options(argc, argv, &o);
  if (parsed != 0) return parsed == 1 ? 0 : 2;
  std::string error;
  if (!tools::make_output_dir(o.out, &error)) {
    std::fprintf(stderr, "hrframes: -o: %s\n", error.c_str());
    return 2;
  }
  lcm::LogFile log(o.log, "r");
  if (!log.good()) {
    std::fprintf(stderr, "hrframes: %s: cannot open as an LCM log (%s)\n", o.log.c_str(),
                 std::strerror(errno));
    return 2;
  }
  const std::string estimates_path = o.out + "/estimates.jsonl";
  FILE* estimates = std::fopen(estimates_path.c_str(), "w");
  if (!estimates) {
    std::fprintf(stderr, "hrframes: %s: cannot write: %s\n", estimates_path.c_str(),
                 std::strerror(errno));
    return 2;
  }
  hrp::depth_frame_t msg;
  fsw_app::reserve_points(&msg, kMaxPoints);
  std::vector<hal::DepthPoint> points(kMaxPoints);
  Counts c;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    if (e->channel == kFrameChannel) {
      ++c.frames;
      if (!write_frame(o, *e, &msg, &points, &c)) ++c.failed;
    } else if (e->channel == kEstimateChannel) {
      hrp::handrail_estimate_t m{};
      if (m.decode(e->data, 0, static_cast<int>(e->datalen)) < 0) {
        std::fprintf(stderr, "hrframes: %s: event %lld (%s) does not decode; skipped\n",
                     o.log.c_str(), static_cast<long long>(e->eventnum), kEstimateChannel);
        ++c.bad_estimates;
        continue;
      }
      if (!in_range(o, static_cast<long>(m.frame_id))) continue;
      std::fprintf(estimates, "%s\n", estimate_to_json(m).c_str());
      ++c.estimates;
    }
  }
  const bool estimates_ok = std::fclose(estimates) == 0;
  if (!estimates_ok) {
    std::fprintf(stderr, "hrframes: %s: write failed\n", estimates_path.c_str());
  }
  std::printf(
      "%s: %ld depth frames, %ld written to %s (%ld outside --frames, %ld failed); %ld estimates "
      "in estimates.jsonl (%ld did not decode)\n",
      o.log.c_str(), c.frames, c.written, o.out.c_str(), c.skipped, c.failed, c.estimates,
      c.bad_estimates);
  if (c.frames == 0) {
    std::printf("no %s messages: record the run with fsw_app --publish-frames --log LOG\n",
                kFrameChannel);
  }
  return c.frames > 0 && c.failed == 0 && c.bad_estimates == 0 && estimates_ok ? 0 : 1;
}
