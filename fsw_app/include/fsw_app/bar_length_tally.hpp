#pragma once
// The length of the handrail in view, learned from the detector's estimates
// with both ends seen (BE). An estimate with one end seen (OE) gives the
// bar's centre only through its length: the centre is half a bar from the
// seen end. The station's handrails come in several lengths (the detector's
// four ISS types run from 0.20 to 1.04 m), so a configured length would put
// an OE centre 10 cm off on a 0.76 m bar when 0.55 m is configured. Until
// the BE lengths agree, an OE estimate is used as one with no end in view
// (the along-bar position is not claimed). The length is kept when the
// filter drops its handrail map: a map is dropped for a transient far more
// often than for another handrail, and another handrail's BE lengths take
// over after three. Fixed memory, no allocation.
#include <array>

namespace fsw_app {

class BarLengthTally {
 public:
  static constexpr int kWindow = 5;            // the newest BE lengths kept
  static constexpr int kMinAgreeing = 3;       // within tolerance of their median
  static constexpr double kToleranceM = 0.02;  // the detector's length: mm-level
  static constexpr double kMinLengthM = 0.05;  // shorter or non-finite: ignored
  static constexpr double kMaxLengthM = 2.0;   // longer: ignored

  // A BE estimate's measured length (end to end); an implausible one is
  // ignored and false returned.
  bool add_both_ends(double length_m);
  // The median of the kept lengths when at least kMinAgreeing of them lie
  // within kToleranceM of it, else a negative number (unknown).
  double length_m() const;
  void reset();

 private:
  std::array<double, kWindow> lengths_m_{};
  int count_ = 0;  // kept, up to kWindow
  int next_ = 0;   // where the next one goes
};

}  // namespace fsw_app
