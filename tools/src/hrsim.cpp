// hrsim: renders a scenario into a folder of organized PCD frames with
// ground truth (truth.jsonl), and optionally a false-colour picture of each
// frame with the true centre lines drawn on it. With --camera raw the
// frames are the raw renderer's phase images (written too, DIR/raw/) through
// the robot's ToF processing.
#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include "common/cli_number.hpp"
#include "common/depth_picture.hpp"
#include "common/output_dir.hpp"
#include "common/progress.hpp"
#include "formats/pcd_io.hpp"
#include "raw_frame_file.hpp"
#include "sim_camera_path.hpp"
#include "sim_hal/ground_truth.hpp"
#include "sim_hal/scenario.hpp"

namespace {

void usage(FILE* out) {
  std::fprintf(out,
               "usage: hrsim SCENARIO.json -o DIR [options]\n"
               "Renders a scenario with the simulated Pico Flexx into DIR/frame_NNNNN.pcd\n"
               "and DIR/truth.jsonl (one JSON object of ground truth per frame).\n\n"
               "options:\n"
               "  -o, --out DIR     output folder (created, with its parents, if missing)\n"
               "  --png             also write DIR/png/frame_NNNNN.png: depth in false colour\n"
               "                    with the true bar centre lines (white) and ends (magenta)\n"
               "  --pcd-format ascii|binary|binary_compressed\n"
               "                    PCD data encoding (default binary; binary_compressed is\n"
               "                    PCL's LZF-compressed form)\n"
               "  --ascii           same as --pcd-format ascii\n"
               "  --camera depth|raw\n"
               "                    depth: the depth renderer (default). raw: the raw\n"
               "                    renderer's phase frames (MODE_9), written as\n"
               "                    DIR/raw/frame_NNNNN.raw (format: tools/README.md), through\n"
               "                    the robot's ToF processing into the PCD frames, on the\n"
               "                    unit's calibration file DIR/tof-calibration.json\n"
               "  --max-frames N    render only the first N frames\n"
               "  --seed N          override the scenario's seed\n"
               "  -h, --help        this text\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenario_path, out_dir;
  bool png = false;
  formats::PcdEncoding encoding = formats::PcdEncoding::kBinary;
  long max_frames = -1;
  long long seed = -1;
  std::string camera_path = "depth";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&](const char* what) -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "hrsim: %s needs a value (see --help)\n", what);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "-o" || a == "--out") {
      out_dir = next("--out");
    } else if (a == "--png") {
      png = true;
    } else if (a == "--ascii") {
      encoding = formats::PcdEncoding::kAscii;
    } else if (a == "--pcd-format") {
      const std::string v = next("--pcd-format");
      if (v == "ascii") {
        encoding = formats::PcdEncoding::kAscii;
      } else if (v == "binary") {
        encoding = formats::PcdEncoding::kBinary;
      } else if (v == "binary_compressed") {
        encoding = formats::PcdEncoding::kBinaryCompressed;
      } else {
        std::fprintf(stderr,
                     "hrsim: --pcd-format must be ascii, binary or binary_compressed, not '%s'\n",
                     v.c_str());
        return 2;
      }
    } else if (a == "--camera") {
      camera_path = next("--camera");
      if (camera_path != "depth" && camera_path != "raw") {
        std::fprintf(stderr, "hrsim: --camera is depth or raw, not '%s'\n", camera_path.c_str());
        return 2;
      }
    } else if (a == "--max-frames" || a == "--seed") {
      long long n = 0;
      std::string why;
      const bool frames = a == "--max-frames";
      if (!tools::parse_whole_number(next(a.c_str()), frames ? 1 : 0,
                                     frames ? 1000000 : static_cast<long long>(INT64_MAX), &n,
                                     &why)) {
        std::fprintf(stderr, "hrsim: %s %s\n", a.c_str(), why.c_str());
        return 2;
      }
      if (frames) {
        max_frames = static_cast<long>(n);
      } else {
        seed = static_cast<decltype(seed)>(n);
      }
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "hrsim: unknown option '%s' (see --help)\n", a.c_str());
      return 2;
    } else if (scenario_path.empty()) {
      scenario_path = a;
    } else {
      std::fprintf(stderr,
                   "hrsim: more than one scenario given ('%s'); render them one at a time\n",
                   a.c_str());
      return 2;
    }
  }
  if (scenario_path.empty() || out_dir.empty()) {
    usage(stderr);
    return 2;
  }
  sim_hal::Scenario scenario;
  std::string error;
  if (!sim_hal::load_scenario(scenario_path, &scenario, &error)) {
    std::fprintf(stderr, "hrsim: %s\n", error.c_str());
    return 1;
  }
  if (seed >= 0) scenario.seed = static_cast<std::uint64_t>(seed);
  const bool raw = camera_path == "raw";
  if (!tools::make_output_dir(out_dir, &error) ||
      (png && !tools::make_output_dir(out_dir + "/png", &error)) ||
      (raw && !tools::make_output_dir(out_dir + "/raw", &error))) {
    std::fprintf(stderr, "hrsim: %s\n", error.c_str());
    return 1;
  }
  std::ofstream truth_out(out_dir + "/truth.jsonl");
  if (!truth_out) {
    std::fprintf(stderr, "hrsim: cannot write %s/truth.jsonl\n", out_dir.c_str());
    return 1;
  }
  const sim_hal::CameraIntrinsics cam = sim_hal::pico_flexx_intrinsics();
  tools::SimCameraPath camera(scenario);
  if (!camera.open(camera_path, out_dir + "/tof-calibration.json", "MODE_9_5FPS_2000", &error)) {
    std::fprintf(stderr, "hrsim: %s\n", error.c_str());
    return 1;
  }
  std::size_t n = scenario.T_world_cam.size();
  if (max_frames >= 0 && static_cast<std::size_t>(max_frames) < n)
    n = static_cast<std::size_t>(max_frames);
  tools::Progress progress("hrsim " + scenario.name, n);
  double render_ms = 0.0;
  for (std::size_t f = 0; f < n; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    hal::DepthFrame frame;
    if (!camera.next(&frame)) break;
    render_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05zu", f);
    if (raw && !tools::write_raw_frame(out_dir + "/raw/" + name + ".raw", *camera.last_raw_frame(),
                                       &error)) {
      std::fprintf(stderr, "\nhrsim: %s\n", error.c_str());
      return 1;
    }
    if (!formats::write_pcd(out_dir + "/" + name + ".pcd", frame, encoding, &error)) {
      std::fprintf(stderr, "\nhrsim: %s\n", error.c_str());
      return 1;
    }
    const sim_hal::FrameTruth truth =
        sim_hal::compute_truth(scenario.scene, cam, scenario.T_world_cam[f], f);
    truth_out << sim_hal::truth_to_json(truth, std::string(name) + ".pcd") << "\n";
    if (png) {
      tools::Image img = tools::depth_picture(frame);
      auto proj = [&](const Eigen::Vector3d& p, Eigen::Vector2d* px) {
        return sim_hal::project(cam, p, px);
      };
      for (const sim_hal::HandrailTruth& h : truth.handrails) {
        tools::draw_segment(&img, proj, h.ends_cam[0], h.ends_cam[1], {255, 255, 255});
        for (int e = 0; e < 2; ++e) {
          Eigen::Vector2d px;
          if (h.end_in_view[e] && sim_hal::project(cam, h.ends_cam[e], &px)) {
            img.disc((px.x() + 0.5) * tools::kPictureScale, (px.y() + 0.5) * tools::kPictureScale,
                     5, {255, 0, 255});
          }
        }
      }
      if (!img.write_png(out_dir + "/png/" + name + ".png", &error)) {
        std::fprintf(stderr, "\nhrsim: %s\n", error.c_str());
        return 1;
      }
    }
    progress.update(f + 1);
  }
  char note[160];
  if (const pico_flexx::RawDepthPipeline* p = camera.pipeline()) {
    const pico_flexx::PipelineCounts c = p->counts();
    std::snprintf(note, sizeof note,
                  "raw path: mean render and processing %.2f ms/frame, ToF processing median "
                  "%.2f ms, %llu dropped, %llu mostly invalid",
                  n ? render_ms / static_cast<double>(n) : 0.0,
                  1e-3 * static_cast<double>(p->processing_median_us()),
                  static_cast<unsigned long long>(c.frames_dropped),
                  static_cast<unsigned long long>(c.frames_mostly_invalid));
  } else {
    std::snprintf(note, sizeof note, "mean render %.2f ms/frame",
                  n ? render_ms / static_cast<double>(n) : 0.0);
  }
  progress.finish(note);
  std::printf("hrsim: wrote %zu frames of '%s' to %s (%s)\n", n, scenario.name.c_str(),
              out_dir.c_str(), note);
  return 0;
}
