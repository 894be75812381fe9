#pragma once
// A recorded frame from tests/data as the estimator's input, through the
// same conversion the tools use.
#include <string>
#include <vector>

#include "estimator/organized_cloud.hpp"
#include "formats/pcd_io.hpp"
#include "frame_convert.hpp"
#include "test_data.hpp"

namespace testing_support {

struct RecordedCloud {
  std::vector<estimator::CloudPoint> points;
  estimator::OrganizedCloud cloud;
};

// False (with *error set) when the file cannot be read.
inline bool load_recorded_cloud(const std::string& name, RecordedCloud* out, std::string* error) {
  formats::PcdFrame pcd;
  if (!formats::read_pcd(data_path(name), &pcd, error)) return false;
  out->cloud = tools::to_estimator_cloud(pcd.view(), &out->points);
  return true;
}

}  // namespace testing_support
