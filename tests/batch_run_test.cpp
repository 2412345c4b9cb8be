// Batch::run with small jobs side by side, and the prepared renders (Session::prepare, run)
// that let it: renders that run at once give the images they give one at a time, and a
// render scene a running render holds is never rebuilt under it.
#include <gtest/gtest.h>

#include <filesystem>
#include <thread>

#include "renderer/image/image_metrics.h"
#include "session/batch.h"
#include "session/session.h"

#ifndef PRISM_SOURCE_DIR
#define PRISM_SOURCE_DIR "."
#endif

namespace prism {
namespace {

namespace fs = std::filesystem;

const std::string kSpheres = PRISM_SOURCE_DIR "/scenes/spheres.gltf";
const std::string kWhitted = PRISM_SOURCE_DIR "/scenes/whitted.gltf";

RenderJob small_job(const std::string& integrator, int spp) {
  RenderJob job;
  job.integrator = integrator;
  job.width = 48;
  job.height = 32;
  job.film.spp = spp;
  return job;
}

SessionOptions threads(int n) {
  SessionOptions o;
  o.threads = n;
  return o;
}

TEST(SessionPrepare, RendersRunningAtOnceGiveTheImagesOfOneAtATime) {
  SceneRequest request;
  request.path = kSpheres;
  const std::vector<RenderJob> jobs = {small_job("shadow", 4), small_job("whitted", 3),
                                       small_job("phong", 5)};
  std::vector<Image> alone;
  {
    Session session(request, threads(1));
    for (const RenderJob& job : jobs) alone.push_back(session.render(job).image);
  }
  Session session(request, threads(2));
  std::vector<Session::Prepared> prepared;
  for (const RenderJob& job : jobs) {
    std::optional<Session::Prepared> p = session.prepare_beside_running(job);
    // Every job shares the first one's render scene.
    ASSERT_TRUE(p.has_value()) << job.integrator;
    prepared.push_back(std::move(*p));
  }
  std::vector<Image> together(jobs.size());
  std::vector<std::thread> runners;
  for (size_t i = 0; i < jobs.size(); ++i)
    runners.emplace_back([&, i] { together[i] = session.run(std::move(prepared[i])).image; });
  for (std::thread& t : runners) t.join();
  for (size_t i = 0; i < jobs.size(); ++i) {
    ASSERT_EQ(together[i].rgba.size(), alone[i].rgba.size()) << jobs[i].integrator;
    EXPECT_TRUE(together[i].rgba == alone[i].rgba) << jobs[i].integrator;
  }
}

TEST(SessionPrepare, ARenderSceneARunningRenderHoldsIsNotChangedUnderIt) {
  SceneRequest request;
  request.path = kSpheres;
  Session session(request, threads(1));
  RenderJob low = small_job("shadow", 1);
  low.build_quality = BuildQuality::low;
  RenderJob high = low;
  high.build_quality = BuildQuality::high;
  RenderJob lit = low;
  lit.background = V3f(0.5f, 0.5f, 0.5f);

  std::optional<Session::Prepared> held = session.prepare_beside_running(low);
  ASSERT_TRUE(held.has_value());  // nothing held yet
  // Another build quality needs another BVH, another background another environment.
  EXPECT_FALSE(session.prepare_beside_running(high).has_value());
  EXPECT_FALSE(session.prepare_beside_running(lit).has_value());
  // Another integrator on the same render scene may run beside it.
  RenderJob phong = low;
  phong.integrator = "phong";
  EXPECT_TRUE(session.prepare_beside_running(phong).has_value());
  const Image first = session.run(std::move(*held)).image;
  held.reset();
  // Released: the next may change it, and the render it held was not disturbed.
  EXPECT_TRUE(session.prepare_beside_running(high).has_value());
  EXPECT_TRUE(first.rgba == session.render(low).image.rgba);
}

class BatchRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("prism_batch_run_test_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::vector<BatchJobSpec> specs(const std::string& folder) const {
    std::vector<BatchJobSpec> out;
    auto add = [&](const std::string& scene, RenderJob render) {
      BatchJobSpec s;
      s.file_index = static_cast<int>(out.size());
      s.name = "job" + std::to_string(out.size());
      s.scene.path = scene;
      s.render = render;
      s.outputs.exr = (dir_ / folder / "{job}.exr").string();
      out.push_back(s);
    };
    add(kSpheres, small_job("shadow", 4));
    add(kSpheres, small_job("whitted", 2));
    RenderJob low = small_job("shadow", 3);
    low.build_quality = BuildQuality::low;  // another BVH: waits for the jobs beside it
    add(kSpheres, low);
    add(kWhitted, small_job("whitted", 4));
    // 300 tiles, more than kSideBySideTilesPerThread per thread: the arena to itself.
    RenderJob large = small_job("shadow", 1);
    large.width = 320;
    large.height = 240;
    large.film.spp = 17;
    add(kWhitted, large);
    add(kWhitted, small_job("phong", 4));
    return out;
  }

  std::vector<JobRecord> run(const std::string& folder, int thread_count) {
    fs::create_directories(dir_ / folder);
    BatchOptions options;
    options.threads = thread_count;
    options.checkpoint_interval = 0.0;
    Batch batch(specs(folder), options);
    return batch.run(batch.plan(), {});
  }

  fs::path dir_;
};

TEST_F(BatchRun, SmallJobsSideBySideGiveTheImagesOfOneAtATime) {
  // One thread renders every job alone; two run the small ones two at a time.
  const std::vector<JobRecord> alone = run("alone", 1);
  const std::vector<JobRecord> together = run("together", 2);
  ASSERT_EQ(together.size(), 6u);
  for (size_t i = 0; i < together.size(); ++i) {
    const JobRecord& r = together[i];
    EXPECT_EQ(r.status, JobStatus::rendered) << r.label << ": " << r.error;
    EXPECT_EQ(r.side_by_side, i != 4) << r.label;
    EXPECT_GT(r.rays, 0u) << r.label;
    EXPECT_EQ(r.rays, alone[i].rays) << r.label;
    const Image a = read_exr(alone[i].output), b = read_exr(r.output);
    ASSERT_EQ(a.rgba.size(), b.rgba.size()) << r.label;
    EXPECT_TRUE(a.rgba == b.rgba) << r.label;
  }
}

}  // namespace
}  // namespace prism
