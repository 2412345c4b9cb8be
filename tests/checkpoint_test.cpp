// Checkpoints: a render stopped at a pass boundary and resumed from its state (directly or
// through a checkpoint file) gives the same image bit for bit as one never stopped, casts
// only the rays that were left, and a checkpoint for anything else is refused with a reason.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "renderer/render_state.h"
#include "session/checkpoint_file.h"
#include "session/session.h"

#ifndef PRISM_SOURCE_DIR
#define PRISM_SOURCE_DIR "."
#endif

namespace prism {
namespace {

namespace fs = std::filesystem;

const char* const kScene = PRISM_SOURCE_DIR "/scenes/spheres.gltf";

RenderJob uniform_job() {
  RenderJob job;
  job.width = 40;
  job.height = 24;
  job.film.spp = 12;
  return job;
}

// A target error that stops some pixels after the first round and keeps others to the end,
// so that a resumed state holds both.
RenderJob adaptive_job() {
  RenderJob job;
  job.width = 40;
  job.height = 24;
  job.film.spp = 48;
  job.film.min_spp = 8;
  job.film.target_error = 0.05f;
  return job;
}

Session& session() {
  static const std::unique_ptr<Session> s = [] {
    SceneRequest request;
    request.path = kScene;
    SessionOptions options;
    options.threads = 2;
    return std::make_unique<Session>(request, options);
  }();
  return *s;
}

bool same_pixels(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

bool same_rays(const RayCounters& a, const RayCounters& b) {
  return std::memcmp(a.rays, b.rays, sizeof a.rays) == 0 &&
         a.discarded_samples == b.discarded_samples;
}

// Stops at the `stop_after`-th pass boundary and returns the state saved there.
RenderState stop_after(const RenderJob& job, int stop_after, const RenderState* resume = nullptr) {
  int polls = 0;
  std::vector<RenderState> saved;
  JobCallbacks callbacks;
  callbacks.pass_seconds = 0.0;  // a boundary after every sample
  callbacks.stop = [&] { return ++polls == stop_after; };
  callbacks.save_checkpoint = [&](const RenderState& s) { saved.push_back(s); };
  callbacks.resume = resume;
  const RenderOutput out = session().render(job, callbacks);
  EXPECT_TRUE(out.result.stopped_at_checkpoint);
  EXPECT_FALSE(out.result.cancelled);
  EXPECT_EQ(1u, saved.size());
  return saved.empty() ? RenderState{} : saved.back();
}

RenderOutput resume_from(const RenderJob& job, const RenderState& state) {
  JobCallbacks callbacks;
  callbacks.pass_seconds = 0.0;
  callbacks.resume = &state;
  callbacks.stop = [] { return false; };
  return session().render(job, callbacks);
}

std::string temp_path(const std::string& name) {
  return (fs::temp_directory_path() /
          ("prism_checkpoint_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

// The resumed render equals the uninterrupted one: pixels, rays, sample counts; and cast
// only the camera rays the state had not.
void expect_resumed_equal(const RenderOutput& resumed, const RenderState& state,
                          const RenderOutput& whole) {
  EXPECT_TRUE(same_pixels(resumed.image, whole.image));
  EXPECT_TRUE(same_rays(resumed.result.rays, whole.result.rays));
  EXPECT_EQ(resumed.result.samples_per_pixel, whole.result.samples_per_pixel);
  EXPECT_EQ(resumed.result.rounds, whole.result.rounds);
  EXPECT_EQ(state.samples_done, resumed.resumed_samples);
  EXPECT_EQ(resumed.result.rays[RayKind::camera] - resumed.result.resumed_rays[RayKind::camera],
            whole.result.rays[RayKind::camera] - state.rays[RayKind::camera]);
  EXPECT_TRUE(same_rays(resumed.result.resumed_rays, state.rays));
}

void check_stop_and_resume(const RenderJob& job, const std::vector<int>& stops) {
  const RenderOutput whole = session().render(job);
  // Checkpoint hooks that save at every boundary and never stop change nothing.
  int saves = 0;
  JobCallbacks every;
  every.pass_seconds = 0.0;
  every.checkpoint_due = [] { return true; };
  every.save_checkpoint = [&](const RenderState&) { ++saves; };
  const RenderOutput with_hooks = session().render(job, every);
  EXPECT_TRUE(same_pixels(with_hooks.image, whole.image));
  EXPECT_TRUE(same_rays(with_hooks.result.rays, whole.result.rays));
  EXPECT_EQ(with_hooks.result.samples_per_pixel, whole.result.samples_per_pixel);
  EXPECT_GT(saves, 2);

  const RenderSettings film = session().film(job);
  for (int k : stops) {
    SCOPED_TRACE("stopped at pass boundary " + std::to_string(k));
    const RenderState state = stop_after(job, k);
    EXPECT_EQ("", state.mismatch(film));
    EXPECT_GT(state.samples_done, 0);
    EXPECT_LT(state.samples_done, film.spp);
    EXPECT_GT(state.rays[RayKind::camera], 0u);
    expect_resumed_equal(resume_from(job, state), state, whole);

    // Through the file.
    const std::string path = temp_path("state");
    write_checkpoint(path, state, "job-a");
    const CheckpointRead read = read_checkpoint(path, film, "job-a");
    fs::remove(path);
    ASSERT_TRUE(read.state) << read.reason;
    expect_resumed_equal(resume_from(job, *read.state), state, whole);

    // Stopped again after resuming, and resumed once more.
    const RenderState second = stop_after(job, 2, &state);
    EXPECT_GT(second.samples_done, state.samples_done);
    expect_resumed_equal(resume_from(job, second), second, whole);
  }
}

TEST(Checkpoint, UniformRenderResumesBitIdentically) {
  check_stop_and_resume(uniform_job(), {1, 4, 9});
}

// Samples grouped into passes by time (the default) give the image of one sample per pass:
// with a pass as long as the whole render, the first pass takes one sample and the second
// all the rest, so there is one boundary to save at.
TEST(Checkpoint, SamplesGroupedIntoLongPassesGiveTheSameImage) {
  const RenderJob job = uniform_job();
  const RenderOutput whole = session().render(job);
  int saves = 0;
  JobCallbacks grouped;
  grouped.pass_seconds = 1e9;
  grouped.checkpoint_due = [] { return true; };
  grouped.save_checkpoint = [&](const RenderState& s) {
    ++saves;
    EXPECT_EQ(1, s.samples_done);
  };
  const RenderOutput out = session().render(job, grouped);
  EXPECT_EQ(1, saves);
  EXPECT_TRUE(same_pixels(out.image, whole.image));
  EXPECT_TRUE(same_rays(out.result.rays, whole.result.rays));
}

// An adaptive job whose target stops some pixels early and keeps others to the end, stopped
// at boundaries inside the first round (8 passes), at its end (the 8th poll: after the
// decision), inside later rounds and late in the render, and resumed.
void check_adaptive_resume(const RenderJob& job) {
  const RenderOutput whole = session().render(job);
  uint32_t fewest = whole.film.spp, most = 0;
  for (uint32_t n : whole.result.samples_per_pixel) {
    fewest = std::min(fewest, n);
    most = std::max(most, n);
  }
  ASSERT_LT(fewest, static_cast<uint32_t>(whole.film.spp));
  ASSERT_GT(most, fewest);
  check_stop_and_resume(job, {3, 8, 11, 30});
}

TEST(Checkpoint, AdaptiveRenderResumesBitIdentically) {
  check_adaptive_resume(adaptive_job());
}

// The image goal's decisions read every pixel's error and sample count, the stopped ones'
// included: a resumed state must hold them as the uninterrupted render did.
TEST(Checkpoint, AdaptiveRenderWithTheImageGoalResumesBitIdentically) {
  RenderJob job = adaptive_job();
  job.film.error_goal = ErrorGoal::image;
  job.film.target_error = 0.02f;
  check_adaptive_resume(job);
}

TEST(Checkpoint, StateAtARoundEndHoldsItsDecision) {
  const RenderJob job = adaptive_job();
  const RenderState state = stop_after(job, 8);
  EXPECT_EQ(8, state.samples_done);
  EXPECT_EQ(1, state.rounds);
  size_t stopped = 0;
  for (uint8_t a : state.active) stopped += a == 0;
  EXPECT_GT(stopped, 0u);
}

TEST(Checkpoint, ResumedRenderReportsItInTheMetadata) {
  const RenderJob job = uniform_job();
  const RenderState state = stop_after(job, 5);
  const RenderOutput out = resume_from(job, state);
  EXPECT_EQ(5, out.resumed_samples);
  bool found = false;
  for (const auto& [key, value] : out.metadata.extra)
    if (key == "resumedSamples") found = value == "5";
  EXPECT_TRUE(found);
}

class CheckpointFile : public ::testing::Test {
 protected:
  void SetUp() override {
    job_ = adaptive_job();
    film_ = session().film(job_);
    state_ = stop_after(job_, 10);
    path_ = temp_path("file");
    write_checkpoint(path_, state_, "fingerprint-1");
    std::ifstream in(path_, std::ios::binary);
    bytes_.assign(std::istreambuf_iterator<char>(in), {});
  }
  void TearDown() override { fs::remove(path_); }

  void rewrite(const std::string& bytes) {
    std::ofstream(path_, std::ios::binary | std::ios::trunc) << bytes;
  }
  std::string refused(const RenderSettings& film, const std::string& fingerprint) {
    const CheckpointRead read = read_checkpoint(path_, film, fingerprint);
    EXPECT_FALSE(read.state);
    EXPECT_FALSE(read.reason.empty());
    EXPECT_EQ(std::string::npos, read.reason.find('\n'));
    return read.reason;
  }

  RenderJob job_;
  RenderSettings film_;
  RenderState state_;
  std::string path_;
  std::string bytes_;
};

TEST_F(CheckpointFile, ReadsBackWhatWasWritten) {
  const CheckpointRead read = read_checkpoint(path_, film_, "fingerprint-1");
  ASSERT_TRUE(read.state) << read.reason;
  const RenderState& s = *read.state;
  EXPECT_EQ(state_.samples_done, s.samples_done);
  EXPECT_EQ(state_.rounds, s.rounds);
  EXPECT_EQ(state_.seconds, s.seconds);
  EXPECT_TRUE(same_rays(state_.rays, s.rays));
  EXPECT_EQ(0, std::memcmp(state_.sums.data(), s.sums.data(), s.sums.size() * sizeof(PixelSums)));
  EXPECT_EQ(0, std::memcmp(state_.first_half.data(), s.first_half.data(),
                           s.first_half.size() * sizeof(PixelSums)));
  EXPECT_EQ(state_.active, s.active);
  EXPECT_EQ(state_.samples_per_pixel, s.samples_per_pixel);
  EXPECT_EQ(0, std::memcmp(state_.error.data(), s.error.data(), s.error.size() * sizeof(float)));
  EXPECT_EQ(ErrorGoal::pixel, s.error_goal);
  // The goal travels in the adaptive byte: an image-goal state reads back as one.
  RenderState image_state = state_;
  image_state.error_goal = ErrorGoal::image;
  RenderSettings image_film = film_;
  image_film.error_goal = ErrorGoal::image;
  write_checkpoint(path_, image_state, "fingerprint-1");
  const CheckpointRead image_read = read_checkpoint(path_, image_film, "fingerprint-1");
  ASSERT_TRUE(image_read.state) << image_read.reason;
  EXPECT_EQ(ErrorGoal::image, image_read.state->error_goal);
}

TEST_F(CheckpointFile, RefusesAWrongFingerprint) {
  EXPECT_NE(std::string::npos, refused(film_, "fingerprint-2").find("another job"));
}

TEST_F(CheckpointFile, RefusesAnotherFilm) {
  RenderSettings other = film_;
  other.width += 4;
  EXPECT_NE(std::string::npos, refused(other, "fingerprint-1").find("44x24"));
  other = film_;
  other.spp *= 2;
  refused(other, "fingerprint-1");
  other = film_;
  other.target_error = 0.0f;  // uniform
  refused(other, "fingerprint-1");
  other = film_;
  other.target_error *= 0.5f;
  refused(other, "fingerprint-1");
  other = film_;
  other.error_goal = ErrorGoal::image;
  EXPECT_NE(std::string::npos, refused(other, "fingerprint-1").find("--error-goal pixel"));
  // And the renderer refuses such a state itself.
  RenderJob wider = job_;
  wider.width += 4;
  EXPECT_NE("", state_.mismatch(session().film(wider)));
  JobCallbacks callbacks;
  callbacks.resume = &state_;
  EXPECT_THROW(session().render(wider, callbacks), std::invalid_argument);
}

TEST_F(CheckpointFile, RefusesATruncatedFile) {
  for (size_t size : {size_t{0}, size_t{7}, size_t{40}, bytes_.size() / 2, bytes_.size() - 1}) {
    SCOPED_TRACE(size);
    rewrite(bytes_.substr(0, size));
    refused(film_, "fingerprint-1");
  }
}

TEST_F(CheckpointFile, RefusesFlippedBytes) {
  // The header's counts (fingerprint length, width, the pixel count), the format version,
  // then a byte in the middle of the sums and the last of the checksum.
  const size_t fingerprint_end = 16 + std::string("fingerprint-1").size();
  const size_t pixel_count = fingerprint_end + 21 + 16 + 4 + 8 * (kRayKindCount + 1);
  for (size_t at : {size_t{8}, size_t{12}, fingerprint_end, fingerprint_end + 1, pixel_count,
                    pixel_count + 2, bytes_.size() / 2, bytes_.size() - 1}) {
    SCOPED_TRACE(at);
    std::string damaged = bytes_;
    damaged[at] = static_cast<char>(damaged[at] ^ 0x10);
    rewrite(damaged);
    refused(film_, "fingerprint-1");
  }
  rewrite(bytes_ + "x");
  refused(film_, "fingerprint-1");
  rewrite(bytes_);
  EXPECT_TRUE(read_checkpoint(path_, film_, "fingerprint-1").state);
}

TEST_F(CheckpointFile, RefusesWhatIsNotACheckpoint) {
  rewrite("not a checkpoint at all, but long enough to have a header of some sort");
  EXPECT_NE(std::string::npos, refused(film_, "fingerprint-1").find("not a Prism checkpoint"));
  fs::remove(path_);
  refused(film_, "fingerprint-1");
}

TEST_F(CheckpointFile, WritingReplacesTheOldCheckpointAndLeavesNoTemporary) {
  const RenderState later = stop_after(job_, 20);
  write_checkpoint(path_, later, "fingerprint-1");
  const CheckpointRead read = read_checkpoint(path_, film_, "fingerprint-1");
  ASSERT_TRUE(read.state) << read.reason;
  EXPECT_EQ(later.samples_done, read.state->samples_done);
  const fs::path dir = fs::path(path_).parent_path();
  const std::string prefix = "." + fs::path(path_).filename().string() + ".tmp-";
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_NE(0u, entry.path().filename().string().rfind(prefix, 0)) << entry.path();
}

}  // namespace
}  // namespace prism
