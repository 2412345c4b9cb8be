#include "apps/stop_signals.h"

#include <signal.h>

#include <atomic>
#include <cstddef>
#include <iterator>

namespace prism {
namespace {

std::atomic<bool> g_interrupted{false}, g_stop{false}, g_checkpoint{false};
std::atomic<int> g_first_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free,
              "the handlers may only touch lock-free atomics");

extern "C" void on_stop_signal(int sig) {
  int none = 0;
  if (sig != SIGUSR2) g_first_signal.compare_exchange_strong(none, sig);
  switch (sig) {
    case SIGINT:
      g_interrupted.store(true);
      ::signal(SIGINT, SIG_DFL);  // the next one is not polite
      break;
    case SIGTERM:
    case SIGUSR1:
      g_stop.store(true);
      break;
    case SIGUSR2:
      g_checkpoint.store(true);
      break;
    default:
      break;
  }
}

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGUSR1, SIGUSR2};
struct sigaction g_previous[std::size(kSignals)];
bool g_installed[std::size(kSignals)] = {};

void install(size_t i) {
  struct sigaction previous {};
  if (::sigaction(kSignals[i], nullptr, &previous) != 0) return;
  if (!(previous.sa_flags & SA_SIGINFO) && previous.sa_handler == SIG_IGN) return;
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // a write in progress goes on rather than failing
  if (::sigaction(kSignals[i], &action, &g_previous[i]) == 0) g_installed[i] = true;
}

}  // namespace

void install_stop_signals(bool checkpoint_signals) {
  g_interrupted = g_stop = g_checkpoint = false;
  g_first_signal = 0;
  for (size_t i = 0; i < std::size(kSignals); ++i)
    if (!g_installed[i] && (kSignals[i] == SIGINT || checkpoint_signals)) install(i);
}

void restore_stop_signals() {
  for (size_t i = 0; i < std::size(kSignals); ++i)
    if (g_installed[i]) {
      ::sigaction(kSignals[i], &g_previous[i], nullptr);
      g_installed[i] = false;
    }
}

bool interrupted() {
  return g_interrupted.load();
}
bool stop_requested() {
  return g_stop.load();
}
bool checkpoint_requested() {
  return g_checkpoint.exchange(false);
}
int stop_signal() {
  return g_first_signal.load();
}

const char* stop_signal_name(int sig) {
  switch (sig) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case SIGUSR1:
      return "SIGUSR1";
    case SIGUSR2:
      return "SIGUSR2";
    default:
      return "a signal";
  }
}

}  // namespace prism
