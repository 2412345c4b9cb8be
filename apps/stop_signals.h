// The signals that end or checkpoint a long render, as flags a render's callbacks poll: the
// handlers only set std::atomic flags (async-signal-safe), so nothing is torn down inside a
// handler and the render decides where to stop.
//   SIGINT            interrupted(): stop starting tiles, write nothing (exit 130)
//   SIGTERM, SIGUSR1  stop_requested(): finish the pass, save a checkpoint, exit 128 + signal
//                     (SIGUSR1 is what Slurm's --signal sends before a time limit)
//   SIGUSR2           checkpoint_requested(): save a checkpoint at the next pass boundary and
//                     carry on
// A second SIGINT kills the process at once, for a render that does not reach a tile
// boundary soon enough.
#pragma once

namespace prism {

// Installs the SIGINT handler, and with `checkpoint_signals` those of SIGTERM, SIGUSR1 and
// SIGUSR2 (without, they keep their default action: a render with nothing to save is just
// terminated). Clears every flag. Signals the process ignores stay ignored.
void install_stop_signals(bool checkpoint_signals);

// Gives the signals back the dispositions they had before install_stop_signals: once the
// render is over, SIGINT and SIGTERM end the process again (during the output's write,
// renderer/image/image_output.h removes its temporary and dies of the signal). The flags
// keep what they saw.
void restore_stop_signals();

// install_stop_signals for a scope: restore() gives the dispositions back once the work that
// may stop early is over (before the outputs are written), and the destructor does it on an
// exception's way out, so no path leaves the handlers installed.
class StopSignalScope {
 public:
  explicit StopSignalScope(bool checkpoint_signals) { install_stop_signals(checkpoint_signals); }
  ~StopSignalScope() { restore(); }
  StopSignalScope(const StopSignalScope&) = delete;
  StopSignalScope& operator=(const StopSignalScope&) = delete;
  void restore() {
    if (installed_) restore_stop_signals();
    installed_ = false;
  }

 private:
  bool installed_ = true;
};

bool interrupted();
bool stop_requested();
// True once per SIGUSR2 received since the last call.
bool checkpoint_requested();
// The first of SIGINT, SIGTERM or SIGUSR1 that arrived, or 0.
int stop_signal();
// "SIGTERM" for SIGTERM, and so on for the signals above; "a signal" otherwise.
const char* stop_signal_name(int signal);

}  // namespace prism
