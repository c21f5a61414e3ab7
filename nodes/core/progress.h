// A node reports how far a long stage has come through this callback, without knowing who displays it.
#pragma once

#include <functional>

namespace scanfill {

// Called with a fraction in [0, 1]; may be called from any thread; must be cheap and thread-safe.
using ProgressFn = std::function<void(double fraction)>;

inline void report(const ProgressFn& progress, double fraction) {
  if (progress) progress(fraction);
}

}  // namespace scanfill
