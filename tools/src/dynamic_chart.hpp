#pragma once
// The dynamic experiment's figure, in the manner of the paper's Figure 17:
// x and y against time, the truth and the filter's estimate (and the
// general-purpose localizer's fixes), one panel each.
#include <string>
#include <vector>

namespace tools {

struct TrackSample {
  double t_s = 0.0;
  double true_x = 0.0, true_y = 0.0;  // m
  double est_x = 0.0, est_y = 0.0;
};
struct FixSample {
  double t_s = 0.0, x = 0.0, y = 0.0;
};

bool write_track_chart(const std::string& path, const std::string& title,
                       const std::vector<TrackSample>& track, const std::vector<FixSample>& gp,
                       std::string* error);

}  // namespace tools
