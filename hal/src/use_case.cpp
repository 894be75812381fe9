#include "hal/use_case.hpp"

#include <iterator>

namespace hal {
namespace {
constexpr UseCase kUseCases[] = {
    {"MODE_9_5FPS_2000", 9, 5, 2000}, {"MODE_9_10FPS_1000", 9, 10, 1000},
    {"MODE_9_15FPS_700", 9, 15, 700}, {"MODE_9_25FPS_450", 9, 25, 450},
    {"MODE_5_35FPS_600", 5, 35, 600}, {"MODE_5_45FPS_500", 5, 45, 500},
};
}  // namespace

const UseCase* use_cases(std::size_t* count) {
  *count = std::size(kUseCases);
  return kUseCases;
}

const UseCase* find_use_case(std::string_view name) {
  for (const UseCase& use_case : kUseCases) {
    if (name == use_case.name) return &use_case;
  }
  return nullptr;
}

}  // namespace hal
