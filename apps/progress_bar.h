// A one-line progress bar with ETA on a terminal's stderr; silent when stderr is not a
// terminal or when asked to be quiet.
#pragma once

#include <chrono>
#include <mutex>

namespace prism {

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled);
  // Safe to call from several threads; redraws at most every 100 ms and on completion.
  void update(int done, int total);
  // Clears the line so later output starts clean.
  void finish();

 private:
  bool enabled_;
  bool drawn_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace prism
