#pragma once
// A bar chart in the manner of the paper's Figure 15: mean and standard
// deviation of each error, the methods side by side.
#include <string>
#include <vector>

#include "eval_metrics.hpp"

namespace tools {

struct ChartSeries {
  std::string name;  // e.g. "basic"
  const Tally* tally;
};

bool write_error_chart(const std::string& path, const std::string& title,
                       const std::vector<ChartSeries>& series, std::string* error);

}  // namespace tools
