#include "apps/progress_bar.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace prism {
namespace {

using Clock = std::chrono::steady_clock;

// "12.3s", "4m05s", "2h13m": short, so the bar keeps the width.
std::string duration(double seconds) {
  char buffer[32];
  if (seconds < 60.0)
    std::snprintf(buffer, sizeof buffer, "%.1fs", seconds);
  else if (seconds < 3600.0)
    std::snprintf(buffer, sizeof buffer, "%dm%02ds", static_cast<int>(seconds / 60.0),
                  static_cast<int>(seconds) % 60);
  else
    std::snprintf(buffer, sizeof buffer, "%dh%02dm", static_cast<int>(seconds / 3600.0),
                  static_cast<int>(seconds / 60.0) % 60);
  return buffer;
}

// The throughput is measured over this much of the most recent time.
constexpr double kRateWindowSeconds = 5.0;

}  // namespace

int terminal_columns() {
  winsize size{};
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
  if (const char* columns = std::getenv("COLUMNS")) {
    const int n = std::atoi(columns);
    if (n > 0) return n;
  }
  return 80;
}

ProgressBar::ProgressBar(bool enabled)
    : enabled_(enabled && isatty(STDERR_FILENO)), start_(Clock::now()) {
  if (!enabled_) return;
  columns_ = terminal_columns();
  // At once: a render's first tiles may take a while to come in.
  std::lock_guard lock(mutex_);
  draw(line(0, 0, 0.0, -1.0, columns_));
}

std::string ProgressBar::line(int done, int total, double elapsed, double eta, int columns) {
  const double fraction = total > 0 ? static_cast<double>(done) / total : 0.0;
  char tail[128];
  std::snprintf(tail, sizeof tail, " %3d%% %d/%d tiles %s ETA %s", static_cast<int>(fraction * 100),
                done, total, duration(elapsed).c_str(), eta < 0.0 ? "?" : duration(eta).c_str());
  std::string text = tail;
  // The bar takes what is left of the line, never the last column (a terminal wraps there).
  const int room = columns - 1 - static_cast<int>(text.size()) - 2;
  if (room >= 10) {
    const int width = std::min(room, 40);
    const int filled = static_cast<int>(fraction * width);
    text = "[" + std::string(static_cast<size_t>(filled), '#') +
           std::string(static_cast<size_t>(width - filled), '.') + "]" + text;
  }
  if (static_cast<int>(text.size()) > columns - 1)
    text.resize(static_cast<size_t>(std::max(0, columns - 1)));
  return text;
}

double ProgressBar::eta(Clock::time_point now, int done, int total) {
  recent_.emplace_back(now, done);
  while (recent_.size() > 2 &&
         std::chrono::duration<double>(now - recent_[1].first).count() > kRateWindowSeconds)
    recent_.pop_front();
  const auto& [then, done_then] = recent_.front();
  const double seconds = std::chrono::duration<double>(now - then).count();
  if (done <= done_then || seconds <= 0.0) return -1.0;
  return (total - done) * seconds / (done - done_then);
}

void ProgressBar::update(int done, int total) {
  if (!enabled_ || total <= 0) return;
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;  // another thread is drawing; never make a worker wait
  const auto now = Clock::now();
  if (done < total && drawn_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  draw(line(done, total, elapsed, eta(now, done, total), columns_));
}

void ProgressBar::phase(const std::string& what) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  std::string text = what;
  if (static_cast<int>(text.size()) > columns_ - 1)
    text.resize(static_cast<size_t>(std::max(0, columns_ - 1)));
  draw(text);
}

void ProgressBar::draw(const std::string& text) {
  last_draw_ = Clock::now();
  drawn_ = true;
  // \033[K clears what a longer line before left behind.
  std::fprintf(stderr, "\r%s\033[K", text.c_str());
  std::fflush(stderr);
}

void ProgressBar::finish() {
  std::lock_guard lock(mutex_);
  if (enabled_ && drawn_) std::fprintf(stderr, "\r\033[K");
  drawn_ = false;
}

}  // namespace prism
