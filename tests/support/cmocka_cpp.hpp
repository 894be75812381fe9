#pragma once
// CMocka 1.1's header has no C++ guards and needs these headers first.
// Its fail() macro would also break the iostream headers, so those come
// before it.
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

extern "C" {
#include <cmocka.h>
}

// Fails the test with a message when |a - b| > tol.
#define assert_near(a, b, tol)                                                 \
  do {                                                                         \
    const double hrp_a_ = (a), hrp_b_ = (b), hrp_t_ = (tol);                   \
    if (!(hrp_a_ - hrp_b_ <= hrp_t_ && hrp_b_ - hrp_a_ <= hrp_t_)) {           \
      print_error("%s = %g, expected %g +- %g\n", #a, hrp_a_, hrp_b_, hrp_t_); \
      fail();                                                                  \
    }                                                                          \
  } while (0)
