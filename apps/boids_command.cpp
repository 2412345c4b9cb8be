#include "apps/boids_command.h"

#include <cstdio>
#include <filesystem>

#include "apps/command_line.h"
#include "simulation/clip_export.h"
#include "simulation/clip_preview.h"
#include "simulation/flock_config.h"

namespace prism {
namespace {

namespace fs = std::filesystem;

int write_frames(const BoidsOptions& o) {
  if (o.config.empty()) throw UsageError("--config: required (or --preview DIR)");
  if (o.output.empty()) throw UsageError("-o: required: the folder the clip is written to");
  FlockConfig config;
  try {
    config = read_flock_config(o.config);
    if (o.frames > 0) config.clip.frames = o.frames;
  } catch (const FlockConfigError& e) {
    throw UsageError(e.what());
  }
  ClipLayout layout;
  try {
    layout = write_clip(config, o.output, o.threads);
  } catch (const FlockConfigError& e) {
    // What only placing the flock finds (no room to spawn) is still the config's fault.
    throw UsageError(o.config + ": " + e.what());
  }
  const double fps = 1.0 / (config.flock.time_step * config.clip.steps_per_frame);
  if (o.verbose)
    std::printf("config %s: time step %.4g s, %d steps per frame\n", o.config.c_str(),
                config.flock.time_step, config.clip.steps_per_frame);
  if (o.quiet) return 0;
  std::printf("wrote %d frame scenes (%d boids, obstacle spheres: %zu, %.4g frames/s) to %s\n",
              layout.frames, config.flock.boids, config.flock.obstacles.size(), fps,
              (layout.dir / "scenes").c_str());
  std::printf("render:  prism batch %s\n", layout.job_file().c_str());
  std::printf("preview: prism boids --preview %s --fps %.4g\n", layout.dir.c_str(), fps);
  return 0;
}

int write_previews(const BoidsOptions& o) {
  const fs::path dir = o.preview;
  const auto frames = rendered_previews(dir / "png");
  if (frames.empty())
    throw UsageError((dir / "png").string() + ": no rendered frames: run prism batch " +
                     (dir / "boids-jobs.json").string() + " first");
  const ClipLayout layout{dir, static_cast<int>(frames.size())};
  write_contact_sheet(frames, layout.contact_sheet());
  if (o.verbose)
    for (const fs::path& frame : frames) std::printf("frame %s\n", frame.c_str());
  if (o.quiet) {
    const std::string video = write_video(frames, layout.video(), o.fps);
    if (!video.empty()) std::fprintf(stderr, "prism: warning: no MP4: %s\n", video.c_str());
    return 0;
  }
  std::printf("wrote %s (%zu frames)\n", layout.contact_sheet().c_str(), frames.size());
  const std::string video = write_video(frames, layout.video(), o.fps);
  if (video.empty())
    std::printf("wrote %s\n", layout.video().c_str());
  else
    std::printf("no MP4: %s\n", video.c_str());
  return 0;
}

}  // namespace

CLI::App* add_boids_command(CLI::App& app, BoidsOptions* o) {
  CLI::App* cmd = app.add_subcommand(
      "boids",
      "Simulate a flock steering around spheres and write it as a batch of frames "
      "(docs/boids.md)");
  CLI::Option* config = cmd->add_option("--config", o->config, "Flock config (.json)");
  CLI::Option* frames =
      cmd->add_option("--frames", o->frames, "Frames to write (default: the config's)")
          ->check(whole_number(1, 100000));
  CLI::Option* output = cmd->add_option("-o,--output", o->output, "Folder the clip is written to");
  cmd->add_option("--threads", o->threads,
                  "Worker threads (0 = all cores); the flock is the same for any")
      ->check(whole_number(0, 1024))
      ->capture_default_str();
  CLI::Option* preview = cmd->add_option(
      "--preview", o->preview,
      "Instead: make the contact sheet and MP4 of a clip folder prism batch has rendered");
  cmd->add_option("--fps", o->fps, "Frames per second of the MP4")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  add_verbosity_flags(cmd, &o->quiet, &o->verbose, "Nothing on stdout",
                      "Also print the config's time step and, with --preview, each frame used");
  preview->excludes(config)->excludes(frames)->excludes(output);
  return cmd;
}

int run_boids(const BoidsOptions& options) {
  return run_reporting_errors(
      [&] { return options.preview.empty() ? write_frames(options) : write_previews(options); });
}

}  // namespace prism
