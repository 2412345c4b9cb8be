// A one-line progress bar with ETA on a terminal's stderr; silent when stderr is not a
// terminal or when asked to be quiet. The line fits the terminal's width (so it never wraps),
// shows at once, and names the phase after the render (writing the files).
#pragma once

#include <chrono>
#include <deque>
#include <mutex>
#include <string>
#include <utility>

namespace prism {

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled);
  // Safe to call from several threads; redraws at most every 100 ms and on completion.
  void update(int done, int total);
  // Replaces the bar by a phase without a count ("writing out.exr"), drawn now.
  void phase(const std::string& what);
  // Clears the line so later output starts clean.
  void finish();

  // The line for `done` of `total` tiles after `elapsed` seconds with `eta` seconds left
  // (negative: not known yet), at most `columns` - 1 characters. Public for its test.
  static std::string line(int done, int total, double elapsed, double eta, int columns);

 private:
  // Seconds left at the rate of the last few seconds' tiles (tiles cost unequally across
  // the frame, so the whole render's mean rate runs behind); negative until two tiles are in.
  double eta(std::chrono::steady_clock::time_point now, int done, int total);
  void draw(const std::string& text);

  bool enabled_;
  bool drawn_ = false;
  int columns_ = 80;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::deque<std::pair<std::chrono::steady_clock::time_point, int>> recent_;  // (when, done)
};

// The width of the terminal on stderr: its window size, else $COLUMNS, else 80.
int terminal_columns();

}  // namespace prism
