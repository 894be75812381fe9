// hrsim: renders a scenario into a folder of organized PCD frames with
// ground truth (truth.jsonl), and optionally a false-colour picture of each
// frame with the true centre lines drawn on it.
#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include "common/depth_picture.hpp"
#include "common/progress.hpp"
#include "formats/pcd_io.hpp"
#include "sim_hal/ground_truth.hpp"
#include "sim_hal/scenario.hpp"

namespace {

void usage(FILE* out) {
  std::fprintf(out,
               "usage: hrsim SCENARIO.json -o DIR [options]\n"
               "Renders a scenario with the simulated Pico Flexx into DIR/frame_NNNNN.pcd\n"
               "and DIR/truth.jsonl (one JSON object of ground truth per frame).\n\n"
               "options:\n"
               "  -o, --out DIR     output folder (created if missing)\n"
               "  --png             also write DIR/png/frame_NNNNN.png: depth in false colour\n"
               "                    with the true bar centre lines (white) and ends (magenta)\n"
               "  --pcd-format ascii|binary|binary_compressed\n"
               "                    PCD data encoding (default binary; binary_compressed is\n"
               "                    PCL's LZF-compressed form)\n"
               "  --ascii           same as --pcd-format ascii\n"
               "  --max-frames N    render only the first N frames\n"
               "  --seed N          override the scenario's seed\n"
               "  -h, --help        this text\n");
}

bool make_dir(const std::string& path) {
  return mkdir(path.c_str(), 0755) == 0 || errno == EEXIST;
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenario_path, out_dir;
  bool png = false;
  formats::PcdEncoding encoding = formats::PcdEncoding::kBinary;
  long max_frames = -1;
  long long seed = -1;
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
    } else if (a == "--max-frames") {
      max_frames = std::atol(next("--max-frames"));
    } else if (a == "--seed") {
      seed = std::atoll(next("--seed"));
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
  if (!make_dir(out_dir) || (png && !make_dir(out_dir + "/png"))) {
    std::fprintf(stderr, "hrsim: cannot create %s: %s\n", out_dir.c_str(), std::strerror(errno));
    return 1;
  }
  std::ofstream truth_out(out_dir + "/truth.jsonl");
  if (!truth_out) {
    std::fprintf(stderr, "hrsim: cannot write %s/truth.jsonl\n", out_dir.c_str());
    return 1;
  }
  const sim_hal::CameraIntrinsics cam = sim_hal::pico_flexx_intrinsics();
  sim_hal::DepthRenderer renderer(cam, scenario.sensor);
  std::size_t n = scenario.T_world_cam.size();
  if (max_frames >= 0 && static_cast<std::size_t>(max_frames) < n)
    n = static_cast<std::size_t>(max_frames);
  std::vector<hal::DepthPoint> points;
  tools::Progress progress("hrsim " + scenario.name, n);
  const std::int64_t period_us = static_cast<std::int64_t>(1e6 / scenario.frame_rate_hz);
  double render_ms = 0.0;
  for (std::size_t f = 0; f < n; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    renderer.render(scenario.scene, scenario.T_world_cam[f], scenario.seed, f, &points);
    render_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const hal::DepthFrame frame{f, static_cast<std::int64_t>(f) * period_us, cam.width, cam.height,
                                points.data()};
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05zu", f);
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
  char note[96];
  std::snprintf(note, sizeof note, "mean render %.2f ms/frame",
                n ? render_ms / static_cast<double>(n) : 0.0);
  progress.finish(note);
  std::printf("hrsim: wrote %zu frames of '%s' to %s (%s)\n", n, scenario.name.c_str(),
              out_dir.c_str(), note);
  return 0;
}
