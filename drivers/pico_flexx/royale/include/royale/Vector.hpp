#pragma once
// royale::Vector: royale's own vector class, here the standard vector with
// royale's additions (count, toStdVector, fromStdVector).
#include <cstddef>
#include <utility>
#include <vector>

namespace royale {

template <typename T>
class Vector : public std::vector<T> {
 public:
  using std::vector<T>::vector;
  Vector() = default;
  Vector(const std::vector<T>& v)
      : std::vector<T>(v) {}  // NOLINT: implicit, so a standard one passes
  Vector(std::vector<T>&& v) : std::vector<T>(std::move(v)) {}  // NOLINT: as above

  std::size_t count() const { return this->size(); }
  std::vector<T> toStdVector() const { return *this; }
  static Vector fromStdVector(const std::vector<T>& v) { return Vector(v); }
};

}  // namespace royale
